#include "penumbra/render/light/uniform_infinite_light.h"

#include <cmath>
#include <numbers>

#include "penumbra/render/sampling.h"

namespace penumbra {

namespace {
constexpr float kPi = std::numbers::pi_v<float>;
}  // namespace

UniformInfiniteLight::UniformInfiniteLight(const SceneParams& params) {
  radiance_ = params.get_rgb("radiance", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(radiance_[c] >= 0.0f && std::isfinite(radiance_[c])))
      params.fail("radiance", "must be finite and non-negative");
  params.check_all_used();
}

void UniformInfiniteLight::preprocess(const Bounds3& b) {
  bounding_sphere(b, center_, radius_);
  radius_ = std::fmax(radius_, 1e-3f);  // an empty scene still gets a finite disc
}

LightSample UniformInfiniteLight::sample_li(Vec3, Vec2 u) const {
  LightSample ls;
  ls.wi = sample_uniform_sphere(u);
  ls.distance = kInfinity;
  ls.li = radiance_;
  ls.pdf = 1.0f / (4.0f * kPi);
  return ls;
}

float UniformInfiniteLight::pdf_li(Vec3, Vec3, const LightPoint&) const {
  return 1.0f / (4.0f * kPi);
}

Rgb UniformInfiniteLight::le(const Ray&) const {
  return radiance_;
}

LightLeSample UniformInfiniteLight::sample_le(Vec2 u_pos, Vec2 u_dir, float time) const {
  LightLeSample s;
  const Vec3 w = sample_uniform_sphere(u_dir);  // the direction light arrives from
  s.ray.o = sample_disc_origin(center_, radius_, w, u_pos);
  s.ray.d = -w;
  s.ray.time = time;
  s.l = radiance_;
  s.pdf_pos = 1.0f / (kPi * radius_ * radius_);
  s.pdf_dir = 1.0f / (4.0f * kPi);
  return s;
}

void UniformInfiniteLight::pdf_le(const Ray&, Vec3, float& pdf_pos, float& pdf_dir) const {
  pdf_pos = 1.0f / (kPi * radius_ * radius_);
  pdf_dir = 1.0f / (4.0f * kPi);
}

Rgb UniformInfiniteLight::power() const {
  // Every direction's radiance crossing the disc of the bounding sphere: 4 pi * pi r^2 * L.
  return radiance_ * (4.0f * kPi * kPi * radius_ * radius_);
}

}  // namespace penumbra
