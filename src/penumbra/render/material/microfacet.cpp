#include "penumbra/render/material/microfacet.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/scene/scene_params.h"

namespace penumbra {

namespace {

// ln Gamma(x) for x >= 1 by Stirling's series after shifting x to at least 8; absolute error below
// 1e-9. Written out because std::lgamma may write the global `signgam` (not thread-safe).
double log_gamma(double x) {
  double shift = 0.0;
  for (; x < 8.0; x += 1.0) shift += std::log(x);
  const double inv = 1.0 / x, inv2 = inv * inv;
  const double series = inv * (1.0 / 12.0 - inv2 * (1.0 / 360.0 - inv2 * (1.0 / 1260.0)));
  return (x - 0.5) * std::log(x) - x + 0.5 * std::log(2.0 * std::numbers::pi) + series - shift;
}

}  // namespace

MicrofacetDistribution::MicrofacetDistribution(float alpha_x, float alpha_y)
    : alpha_x_(std::max(alpha_x, 1e-4f)), alpha_y_(std::max(alpha_y, 1e-4f)) {}

float MicrofacetDistribution::d(Vec3 h) const {
  if (!(h.z > 0.0f)) return 0.0f;
  // D(h) = 1 / (pi ax ay (hx^2/ax^2 + hy^2/ay^2 + hz^2)^2) for a unit h: the ellipsoid form of
  // Trowbridge-Reitz, equal to Walter et al.'s expression in tan(theta_h).
  const float x = h.x / alpha_x_, y = h.y / alpha_y_;
  const float e = x * x + y * y + h.z * h.z;
  return 1.0f / (std::numbers::pi_v<float> * alpha_x_ * alpha_y_ * e * e);
}

float MicrofacetDistribution::lambda(Vec3 w) const {
  const float z2 = w.z * w.z;
  if (!(z2 > 0.0f)) return INFINITY;  // grazing: everything is masked
  // alpha(phi)^2 tan^2(theta) of the direction, for the stretched (anisotropic) surface.
  const float a2_tan2 = (alpha_x_ * alpha_x_ * w.x * w.x + alpha_y_ * alpha_y_ * w.y * w.y) / z2;
  return 0.5f * (std::sqrt(1.0f + a2_tan2) - 1.0f);
}

float MicrofacetDistribution::g2_transmission(Vec3 wo, Vec3 wi) const {
  const double lo = lambda(wo), li = lambda(wi);
  if (!std::isfinite(lo) || !std::isfinite(li)) return 0.0f;
  // Integral over microfacet heights of C1(h)^Lambda(wo) (1 - C1(h))^Lambda(wi): the Beta function.
  return static_cast<float>(
      std::exp(log_gamma(1.0 + lo) + log_gamma(1.0 + li) - log_gamma(2.0 + lo + li)));
}

float MicrofacetDistribution::d_visible(Vec3 w, Vec3 h) const {
  if (!(w.z > 0.0f)) return 0.0f;
  const float wh = dot(w, h);
  if (!(wh > 0.0f)) return 0.0f;
  return g1(w) * wh * d(h) / w.z;
}

Vec3 MicrofacetDistribution::sample_visible(Vec3 w, Vec2 u) const {
  // Stretch the view so the ellipsoid of normals becomes the unit hemisphere.
  const Vec3 v = normalize(Vec3{alpha_x_ * w.x, alpha_y_ * w.y, w.z});
  // Orthonormal basis (t1, t2, v), t1 horizontal; any t1 when v is the pole.
  const float len2 = v.x * v.x + v.y * v.y;
  const Vec3 t1 = len2 > 0.0f ? Vec3{-v.y, v.x, 0.0f} / std::sqrt(len2) : Vec3{1, 0, 0};
  const Vec3 t2 = cross(v, t1);
  // Uniform point on the projected hemisphere: a disc whose lower half is squashed by v.z.
  const float r = std::sqrt(u.x), phi = 2.0f * std::numbers::pi_v<float> * u.y;
  const float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  const float s = 0.5f * (1.0f + v.z);
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  // Lift the point onto the hemisphere around v, then unstretch the normal.
  const Vec3 n = t1 * p1 + t2 * p2 + v * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return normalize(Vec3{alpha_x_ * n.x, alpha_y_ * n.y, std::max(0.0f, n.z)});
}

float read_roughness(const SceneParams& params) {
  const float r = params.get_float("roughness", 0.3f);
  if (!(r >= 0.0f && r <= 1.0f)) params.fail("roughness", "must lie in [0, 1]");
  return r;
}

}  // namespace penumbra
