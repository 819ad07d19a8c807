#pragma once
/// A constant environment: the same radiance from every direction (the scene's background).
#include "penumbra/render/light/light.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Radiance L arriving from every direction. Incident directions are sampled uniformly on the
/// sphere (density 1 / 4 pi); emitted rays start on a disc of the scene's bounding-sphere radius
/// facing the sampled direction, so every ray that can reach the scene is covered (pbrt-v4's
/// UniformInfiniteLight). Parameters: radiance (RGB, default 1).
class UniformInfiniteLight final : public Light {
 public:
  explicit UniformInfiniteLight(Rgb radiance) : radiance_(radiance) {}
  explicit UniformInfiniteLight(const SceneParams& params);
  LightKind kind() const override { return LightKind::kInfinite; }
  void preprocess(const Bounds3& scene_bounds) override;
  LightSample sample_li(Vec3 p, Vec2 u) const override;
  float pdf_li(Vec3 p, Vec3 wi, const LightPoint& hit) const override;
  Rgb le(const Ray& ray) const override;
  LightLeSample sample_le(Vec2 u_pos, Vec2 u_dir, float time) const override;
  void pdf_le(const Ray& ray, Vec3 n, float& pdf_pos, float& pdf_dir) const override;
  Rgb power() const override;

 private:
  Rgb radiance_;
  Vec3 center_;
  float radius_ = 1;
};

}  // namespace penumbra
