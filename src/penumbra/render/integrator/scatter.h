#pragma once
/// One bounce of a camera path by BSDF sampling, shared by the integrators that follow specular
/// and glossy surfaces before estimating the rest (photon, sppm).
#include <cmath>
#include <optional>

#include "penumbra/render/material/material.h"
#include "penumbra/render/sampler/sampler.h"
#include "penumbra/render/surface_interaction.h"

namespace penumbra {

/// Samples the BSDF `m` (resolved at si) for radiance: on success multiplies beta by
/// f |cos| / pdf, moves `ray` (keeping its time) to leave si in the sampled direction and returns
/// the sample; returns none when the BSDF gives nothing (the path ends). Always draws one 1D and
/// one 2D sample.
inline std::optional<BsdfSample> scatter(const SurfaceInteraction& si, const Material& m,
                                         Sampler& sampler, Rgb& beta, Ray& ray) {
  const float uc = sampler.get_1d();
  const Vec2 u = sampler.get_2d();
  auto bs = m.sample(si.to_local(si.wo), uc, u, TransportMode::kRadiance);
  if (!bs || bs->f.is_black() || !(bs->pdf > 0.0f)) return std::nullopt;
  const Vec3 wi = si.to_world(bs->wi);
  beta *= bs->f * (std::fabs(dot(wi, si.ns)) / bs->pdf);
  ray = si.spawn_ray(wi, ray.time);
  return bs;
}

}  // namespace penumbra
