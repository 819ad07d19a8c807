#pragma once
/// `whitted`: recursive ray tracing (Whitted 1980, "An Improved Illumination Model for Shaded
/// Display", CACM 23(6)).
#include <memory>
#include <vector>

#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/light/light.h"

namespace penumbra {

/// Emission, direct light from point lights with hard shadows (one shadow ray per light), and
/// recursion along perfectly specular directions (mirror reflection, Fresnel-weighted reflection and
/// refraction, total internal reflection) up to max_depth bounces. Emissive shapes light the scene
/// through EmitterPointLight stand-ins. Parameters: max_depth (overrides the scene's).
class WhittedIntegrator final : public Integrator {
 public:
  WhittedIntegrator(const World& world, const ParamList& params, int max_depth);
  std::string name() const override { return "whitted"; }
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override;

 private:
  Rgb trace(const Ray& ray, int depth, Sampler& sampler, RayCounter& counter) const;

  const World& world_;
  int max_depth_;
  std::vector<const Light*> lights_;                 ///< scene lights and stand-ins
  std::vector<std::unique_ptr<Light>> stand_ins_;    ///< owned stand-ins for emitters
};

}  // namespace penumbra
