#pragma once
/// An isotropic point light.
#include "penumbra/render/light/light.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Point light of radiant intensity I (W/sr) at a position. Parameters: position, intensity (RGB).
class PointLight final : public Light {
 public:
  PointLight(Vec3 position, Rgb intensity) : position_(position), intensity_(intensity) {}
  explicit PointLight(const SceneParams& params);
  LightSample sample_li(Vec3 p, Vec2 u) const override;
  Rgb power() const override;

 private:
  Vec3 position_;
  Rgb intensity_;
};

}  // namespace penumbra
