#pragma once
/// A directional light: parallel rays from infinitely far away (the sun; pbrt-v4's DistantLight).
#include "penumbra/render/light/light.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Light of irradiance E (W/m^2 on a surface perpendicular to it) travelling along one direction.
/// Parameters: direction (the direction the light travels, e.g. [0, -1, 0] shines straight down;
/// any non-zero length, normalised), irradiance (RGB, default 1). Emitted rays start on a disc of
/// the scene's bounding-sphere radius, perpendicular to the direction and outside the scene, so
/// every ray that reaches the scene is covered; the power is E times the disc's area.
class DirectionalLight final : public Light {
 public:
  /// Light along `direction` (non-zero, normalised here) of irradiance `irradiance`.
  DirectionalLight(Vec3 direction, Rgb irradiance);
  explicit DirectionalLight(const SceneParams& params);
  LightKind kind() const override { return LightKind::kDeltaDirection; }
  /// Keeps the scene's bounding sphere (for emitted rays and the power).
  void preprocess(const Bounds3& scene_bounds) override;
  /// wi = -direction from every point, unbounded, pdf 1 (a delta).
  LightSample sample_li(Vec3 p, Vec2 u) const override;
  float pdf_li(Vec3, Vec3, const LightPoint&) const override { return 0.0f; }
  /// Origin uniform on the disc (density 1 / (pi r^2)), direction the light's (density 1, delta).
  LightLeSample sample_le(Vec2 u_pos, Vec2 u_dir, float time) const override;
  /// pdf_pos = 1 / (pi r^2); pdf_dir = 0 (a delta in direction).
  void pdf_le(const Ray& ray, Vec3 n, float& pdf_pos, float& pdf_dir) const override;
  Rgb power() const override;
  /// The unit direction the light travels.
  Vec3 direction() const { return direction_; }

 private:
  Vec3 direction_;
  Rgb irradiance_;
  Vec3 center_;
  float radius_ = 1;
};

}  // namespace penumbra
