#include "penumbra/render/light/point_light.h"

#include <cmath>
#include <numbers>

#include "penumbra/render/sampling.h"

namespace penumbra {

PointLight::PointLight(const SceneParams& params) {
  position_ = params.require_vec3("position");
  intensity_ = params.get_rgb("intensity", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(intensity_[c] >= 0.0f && std::isfinite(intensity_[c])))
      params.fail("intensity", "must be finite and non-negative");
  params.check_all_used();
}

LightSample PointLight::sample_li(Vec3 p, Vec2) const {
  const Vec3 d = position_ - p;
  const float d2 = dot(d, d);
  if (!(d2 > 0.0f)) return {};  // at the light itself: no direction
  const float dist = std::sqrt(d2);
  return {d / dist, dist, intensity_ / d2, 1.0f, true};
}

LightLeSample PointLight::sample_le(Vec2, Vec2 u_dir, float time) const {
  LightLeSample s;
  s.ray.o = position_;
  s.ray.d = sample_uniform_sphere(u_dir);
  s.ray.time = time;
  s.l = intensity_;
  s.pdf_pos = 1.0f;
  s.pdf_dir = 1.0f / (4.0f * std::numbers::pi_v<float>);
  return s;
}

void PointLight::pdf_le(const Ray&, Vec3, float& pdf_pos, float& pdf_dir) const {
  pdf_pos = 0.0f;  // a delta in position: no density to compare against
  pdf_dir = 1.0f / (4.0f * std::numbers::pi_v<float>);
}

Rgb PointLight::power() const {
  return intensity_ * (4.0f * std::numbers::pi_v<float>);
}

}  // namespace penumbra
