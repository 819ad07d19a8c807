#include "penumbra/render/light/spot_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/core/error.h"

namespace penumbra {

namespace {
constexpr float kPi = std::numbers::pi_v<float>;

/// True when `d` can be normalised.
bool usable_direction(Vec3 d) {
  return is_finite(d) && max_component(abs(d)) > 0.0f;
}

/// Why the angles are out of range, or "" when they are fine (and which key is wrong).
const char* angle_problem(float cone_angle, float cone_delta, const char*& key) {
  key = "cone_angle";
  if (!(cone_angle > 0.0f && cone_angle <= 180.0f)) return "must be in (0, 180] degrees";
  key = "cone_delta";
  if (!(cone_delta >= 0.0f && cone_delta <= cone_angle))
    return "must be in [0, cone_angle] degrees";
  return "";
}

float radians(float deg) {
  return deg * (kPi / 180.0f);
}
}  // namespace

float spot_smoothstep(float x, float a, float b) {
  if (a == b) return x < a ? 0.0f : 1.0f;
  const float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

float sample_smoothstep_unit(float u) {
  u = std::clamp(u, 0.0f, 1.0f);
  float lo = 0.0f, hi = 1.0f, t = 0.5f;
  for (int i = 0; i < 40; ++i) {
    const float f = t * t * t * (2.0f - t) - u;  // F(t) - u, increasing in t
    if (std::fabs(f) < 1e-7f) break;
    (f < 0.0f ? lo : hi) = t;
    // A Newton step with F'(t) = 6t^2 - 4t^3; bisection when it leaves the bracket.
    const float d = t * t * (6.0f - 4.0f * t);
    const float next = d > 0.0f ? t - f / d : -1.0f;
    t = next > lo && next < hi ? next : 0.5f * (lo + hi);
    if (hi - lo < 1e-7f) break;
  }
  return t;
}

SpotLight::SpotLight(Vec3 position, Vec3 direction, Rgb intensity, float cone_angle_deg,
                     float cone_delta_deg)
    : position_(position), intensity_(intensity) {
  if (!usable_direction(direction)) throw Error("spot light: direction must be non-zero");
  const char* key = nullptr;
  const std::string problem = angle_problem(cone_angle_deg, cone_delta_deg, key);
  if (!problem.empty()) throw Error(std::string("spot light: ") + key + " " + problem);
  init(direction, cone_angle_deg, cone_delta_deg);
}

SpotLight::SpotLight(const SceneParams& params) {
  position_ = params.require_vec3("position");
  if (!is_finite(position_)) params.fail("position", "must be finite");
  const bool has_dir = params.has("direction"), has_at = params.has("look_at");
  if (has_dir == has_at) params.fail("direction", "give exactly one of direction and look_at");
  Vec3 d;
  if (has_dir) {
    d = params.require_vec3("direction");
    if (!usable_direction(d)) params.fail("direction", "must be a finite, non-zero vector");
  } else {
    d = params.require_vec3("look_at") - position_;
    if (!usable_direction(d)) params.fail("look_at", "must be finite and differ from position");
  }
  intensity_ = params.get_rgb("intensity", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(intensity_[c] >= 0.0f && std::isfinite(intensity_[c])))
      params.fail("intensity", "must be finite and non-negative");
  const float angle = params.get_float("cone_angle", 30.0f);
  const float delta = params.get_float("cone_delta", 5.0f);
  const char* key = nullptr;
  const std::string problem = angle_problem(angle, delta, key);
  if (!problem.empty()) params.fail(key, problem);
  params.check_all_used();
  init(d, angle, delta);
}

void SpotLight::init(Vec3 direction, float cone_angle_deg, float cone_delta_deg) {
  // Normalised after scaling by the largest component: robust to tiny and huge vectors.
  axis_ = normalize(direction / max_component(abs(direction)));
  orthonormal_basis(axis_, tangent_, bitangent_);
  cos_end_ = std::cos(radians(cone_angle_deg));
  cos_start_ = std::cos(radians(cone_angle_deg - cone_delta_deg));
}

float SpotLight::falloff(float cos_theta) const {
  return spot_smoothstep(cos_theta, cos_end_, cos_start_);
}

Rgb SpotLight::intensity(Vec3 w) const {
  return intensity_ * falloff(dot(w, axis_));
}

LightSample SpotLight::sample_li(Vec3 p, Vec2) const {
  const Vec3 d = position_ - p;
  const float d2 = dot(d, d);
  if (!(d2 > 0.0f)) return {};  // at the light itself: no direction
  const float dist = std::sqrt(d2);
  const Vec3 wi = d / dist;
  return {wi, dist, intensity(-wi) / d2, 1.0f, true};
}

float SpotLight::pdf_dir(float cos_theta) const {
  // pbrt-v4's two sections combine to a density proportional to the falloff:
  // falloff / (2 pi ((1 - cos_start) + (cos_start - cos_end) / 2)).
  const float k = 2.0f * kPi * ((1.0f - cos_start_) + 0.5f * (cos_start_ - cos_end_));
  return k > 0.0f ? falloff(cos_theta) / k : 0.0f;
}

LightLeSample SpotLight::sample_le(Vec2 u_pos, Vec2 u_dir, float time) const {
  // Choose the full cone (weight 1 - cos_start) or the falloff band (weight (cos_start -
  // cos_end) / 2, the smoothstep's integral over cos theta).
  const float p_cone = 1.0f - cos_start_, p_band = 0.5f * (cos_start_ - cos_end_);
  float cos_theta;
  if (u_pos.x * (p_cone + p_band) < p_cone) {
    cos_theta = 1.0f - u_dir.x * p_cone;  // uniform in solid angle within cos_start
  } else {
    const float t = sample_smoothstep_unit(u_dir.x);
    cos_theta = cos_end_ + t * (cos_start_ - cos_end_);
  }
  cos_theta = std::clamp(cos_theta, -1.0f, 1.0f);
  const float sin_theta = std::sqrt(std::fmax(0.0f, 1.0f - cos_theta * cos_theta));
  const float phi = 2.0f * kPi * u_dir.y;
  LightLeSample s;
  s.ray.o = position_;
  s.ray.d = normalize(tangent_ * (sin_theta * std::cos(phi)) +
                      bitangent_ * (sin_theta * std::sin(phi)) + axis_ * cos_theta);
  s.ray.time = time;
  s.l = intensity_ * falloff(cos_theta);
  s.pdf_pos = 1.0f;
  s.pdf_dir = pdf_dir(cos_theta);
  return s;
}

void SpotLight::pdf_le(const Ray& ray, Vec3, float& pdf_pos, float& pdf_dir_out) const {
  pdf_pos = 0.0f;  // a delta in position: no density to compare against
  pdf_dir_out = pdf_dir(dot(normalize(ray.d), axis_));
}

Rgb SpotLight::power() const {
  return intensity_ * (2.0f * kPi * ((1.0f - cos_start_) + 0.5f * (cos_start_ - cos_end_)));
}

}  // namespace penumbra
