#include "penumbra/render/light/point_light.h"

#include <numbers>

namespace penumbra {

PointLight::PointLight(const SceneParams& params) {
  position_ = params.require_vec3("position");
  intensity_ = params.get_rgb("intensity", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(intensity_[c] >= 0.0f)) params.fail("intensity", "must be non-negative");
  params.check_all_used();
}

LightSample PointLight::sample_li(Vec3 p, Vec2) const {
  const Vec3 d = position_ - p;
  const float d2 = dot(d, d);
  const float dist = std::sqrt(d2);
  return {d / dist, dist, intensity_ / d2, 1.0f, true};
}

Rgb PointLight::power() const { return intensity_ * (4.0f * std::numbers::pi_v<float>); }

}  // namespace penumbra
