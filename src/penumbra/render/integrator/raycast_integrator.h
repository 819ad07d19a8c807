#pragma once
/// `raycast`: the first hit only, the debugging view.
#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"

namespace penumbra {

/// Shades the first hit by its shading normal (mode=normal: (n + 1) / 2), its albedo
/// (mode=albedo; emitters show their radiance) or albedo times |cos| to the eye (mode=eyelight,
/// the default, which shows shape). Misses show the background.
class RaycastIntegrator final : public SamplingIntegrator {
 public:
  enum class Mode { kNormal, kAlbedo, kEyelight };
  RaycastIntegrator(const World& world, const ParamList& params);
  std::string name() const override;
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override;

 private:
  const World& world_;
  Mode mode_;
};

}  // namespace penumbra
