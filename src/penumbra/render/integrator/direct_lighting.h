#pragma once
/// Direct lighting by light sampling alone (next-event estimation without MIS), shared by the
/// integrators that find the rest of the light another way (photon maps, SPPM, radiosity's
/// final gather).
#include "penumbra/render/light/light_sampler.h"
#include "penumbra/render/material/material.h"
#include "penumbra/render/sampler/sampler.h"
#include "penumbra/render/surface_interaction.h"
#include "penumbra/render/world.h"

namespace penumbra {

/// One light sample's estimate of the radiance reflected towards wo (local frame) at si by the
/// non-specular part of m: f Li |cos| / (pmf pdf), zero when the shadow ray is blocked. Always
/// draws one 1D and one 2D sample from `sampler`, so every vertex takes the same dimensions.
Rgb estimate_direct(const World& world, const LightSampler& lights, const SurfaceInteraction& si,
                    const Material& m, Vec3 wo, float time, Sampler& sampler, RayCounter& counter);

}  // namespace penumbra
