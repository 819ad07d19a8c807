#pragma once
/// A spot light: a point light whose intensity is confined to a cone with a smooth edge, as
/// pbrt-v4's SpotLight (Pharr, Jakob, Humphreys 2023, "Physically Based Rendering", 4th ed.,
/// section 12.2.1).
#include "penumbra/render/light/light.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Point light at a position aimed along a unit axis. Its radiant intensity towards a unit
/// direction w at angle theta from the axis is I * smoothstep(cos_end, cos_start, cos theta), with
/// cos_end = cos(cone_angle) (no light beyond) and cos_start = cos(cone_angle - cone_delta) (full
/// intensity within). Parameters: position; look_at or direction; intensity (RGB W/sr);
/// cone_angle (degrees, default 30) and cone_delta (degrees, default 5).
class SpotLight final : public Light {
 public:
  /// A spot light at `position` aimed along `direction` (any non-zero length), angles in degrees;
  /// throws Error for a zero direction or angles out of range (0 < cone_angle <= 180,
  /// 0 <= cone_delta <= cone_angle).
  SpotLight(Vec3 position, Vec3 direction, Rgb intensity, float cone_angle_deg,
            float cone_delta_deg);
  /// Reads the scene file's parameters; errors name their JSON path.
  explicit SpotLight(const SceneParams& params);
  LightKind kind() const override { return LightKind::kDeltaPosition; }
  LightSample sample_li(Vec3 p, Vec2 u) const override;
  float pdf_li(Vec3, Vec3, const LightPoint&) const override { return 0.0f; }
  /// Emits within the cone with density proportional to the intensity: u_pos.x picks the full
  /// cone or the falloff band (pbrt-v4's two sections), u_dir the direction within it, so every
  /// ray's beta is the power.
  LightLeSample sample_le(Vec2 u_pos, Vec2 u_dir, float time) const override;
  void pdf_le(const Ray& ray, Vec3 n, float& pdf_pos, float& pdf_dir) const override;
  /// I 2 pi ((1 - cos_start) + (cos_start - cos_end) / 2): the smoothstep integrates to half the
  /// band's extent in cos theta.
  Rgb power() const override;

  /// The falloff factor in [0, 1] for a direction with cosine `cos_theta` to the axis.
  float falloff(float cos_theta) const;
  /// Radiant intensity towards the unit direction w.
  Rgb intensity(Vec3 w) const;
  /// Cosine of the angle where the light ends (cone_angle).
  float cos_end() const { return cos_end_; }
  /// Cosine of the angle where the falloff starts (cone_angle - cone_delta).
  float cos_start() const { return cos_start_; }
  /// The unit axis.
  Vec3 axis() const { return axis_; }

 private:
  void init(Vec3 direction, float cone_angle_deg, float cone_delta_deg);
  /// Solid-angle density of emitting towards a direction of cosine `cos_theta` to the axis.
  float pdf_dir(float cos_theta) const;

  Vec3 position_, axis_, tangent_, bitangent_;
  Rgb intensity_;
  float cos_end_ = 0, cos_start_ = 1;
};

/// pbrt-v4's smoothstep: 0 below a, 1 above b, 3t^2 - 2t^3 between (t = (x - a) / (b - a)); a
/// step at a when a == b.
float spot_smoothstep(float x, float a, float b);

/// Inverts the normalised integral of the smoothstep on [0, 1], F(t) = 2t^3 - t^4, at u in [0, 1]
/// (Newton's method safeguarded by bisection, as pbrt-v4's SampleSmoothStep).
float sample_smoothstep_unit(float u);

}  // namespace penumbra
