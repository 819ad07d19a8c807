#include "penumbra/render/light/directional_light.h"

#include <cmath>
#include <numbers>

#include "penumbra/core/error.h"
#include "penumbra/render/sampling.h"

namespace penumbra {

namespace {
constexpr float kPi = std::numbers::pi_v<float>;

/// True when `d` can be normalised.
bool usable_direction(Vec3 d) {
  return is_finite(d) && max_component(abs(d)) > 0.0f;
}

/// `d` normalised, robust to tiny and huge components (scaled by its largest one first).
Vec3 unit(Vec3 d) {
  return normalize(d / max_component(abs(d)));
}
}  // namespace

DirectionalLight::DirectionalLight(Vec3 direction, Rgb irradiance) : irradiance_(irradiance) {
  if (!usable_direction(direction)) throw Error("directional light: direction must be non-zero");
  direction_ = unit(direction);
}

DirectionalLight::DirectionalLight(const SceneParams& params) {
  const Vec3 d = params.require_vec3("direction");
  if (!usable_direction(d)) params.fail("direction", "must be a finite, non-zero vector");
  direction_ = unit(d);
  irradiance_ = params.get_rgb("irradiance", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(irradiance_[c] >= 0.0f && std::isfinite(irradiance_[c])))
      params.fail("irradiance", "must be finite and non-negative");
  params.check_all_used();
}

void DirectionalLight::preprocess(const Bounds3& b) {
  bounding_sphere(b, center_, radius_);
  radius_ = std::fmax(radius_, 1e-3f);  // an empty scene still gets a finite disc
}

LightSample DirectionalLight::sample_li(Vec3, Vec2) const {
  return {-direction_, kInfinity, irradiance_, 1.0f, true};
}

LightLeSample DirectionalLight::sample_le(Vec2 u_pos, Vec2, float time) const {
  // A point of the disc tangent to the bounding sphere on the side the light comes from.
  LightLeSample s;
  s.ray.o = sample_disc_origin(center_, radius_, -direction_, u_pos);
  s.ray.d = direction_;
  s.ray.time = time;
  s.l = irradiance_;
  s.pdf_pos = 1.0f / (kPi * radius_ * radius_);
  s.pdf_dir = 1.0f;
  return s;
}

void DirectionalLight::pdf_le(const Ray&, Vec3, float& pdf_pos, float& pdf_dir) const {
  pdf_pos = 1.0f / (kPi * radius_ * radius_);
  pdf_dir = 0.0f;  // a delta in direction: no density to compare against
}

Rgb DirectionalLight::power() const {
  return irradiance_ * (kPi * radius_ * radius_);
}

}  // namespace penumbra
