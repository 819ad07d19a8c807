#pragma once
/// `whitted`: recursive ray tracing (Whitted 1980, "An Improved Illumination Model for Shaded
/// Display", CACM 23(6)).
#include <memory>
#include <vector>

#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/light/emitter_point_light.h"
#include "penumbra/render/light/light.h"

namespace penumbra {

/// Emission, direct light from point lights with hard shadows (one shadow ray per light), and
/// recursion along perfectly specular directions (mirror reflection, Fresnel-weighted reflection and
/// refraction, total internal reflection) up to max_depth bounces. Emissive shapes light the scene
/// through EmitterPointLight stand-ins; infinite lights are only seen, not sampled (the
/// background of rays that miss). Parameters: max_depth (overrides the scene's).
class WhittedIntegrator final : public SamplingIntegrator {
 public:
  WhittedIntegrator(const World& world, const ParamList& params, int max_depth);
  std::string name() const override { return "whitted"; }
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override;

 private:
  Rgb trace(const Ray& ray, int depth, Sampler& sampler, RayCounter& counter) const;

  const World& world_;
  int max_depth_;
  std::vector<const Light*> lights_;        ///< the scene's delta lights
  std::vector<EmitterPointLight> stand_ins_;  ///< one point stand-in per emissive shape
};

}  // namespace penumbra
