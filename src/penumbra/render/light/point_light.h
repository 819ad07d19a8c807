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
  LightKind kind() const override { return LightKind::kDeltaPosition; }
  LightSample sample_li(Vec3 p, Vec2 u) const override;
  float pdf_li(Vec3, Vec3, const LightPoint&) const override { return 0.0f; }
  /// Emits uniformly in all directions from the position (u_pos unused).
  LightLeSample sample_le(Vec2 u_pos, Vec2 u_dir, float time) const override;
  void pdf_le(const Ray& ray, Vec3 n, float& pdf_pos, float& pdf_dir) const override;
  Rgb power() const override;

 private:
  Vec3 position_;
  Rgb intensity_;
};

}  // namespace penumbra
