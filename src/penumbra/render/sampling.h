#pragma once
/// Warping uniform samples to directions and points.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/core/bounds.h"
#include "penumbra/core/vec.h"
#include "penumbra/geometry/sphere_direction.h"  // sample_uniform_sphere

namespace penumbra {

/// sin and cos of a in [-pi/4, pi/4] by their Taylor polynomials to a^9 and a^10: the first
/// omitted terms are below 2e-9 there, so the results are within about an ulp of the true values
/// (checked against libm in sampler_test), without the call to sincosf that cost a third of
/// diffuse sampling.
inline void sin_cos_quarter(float a, float& s, float& c) {
  const float a2 = a * a;
  s = a *
      (1.0f + a2 * (-1.0f / 6 + a2 * (1.0f / 120 + a2 * (-1.0f / 5040 + a2 * (1.0f / 362880)))));
  c = 1.0f + a2 * (-0.5f + a2 * (1.0f / 24 + a2 * (-1.0f / 720 +
                                                   a2 * (1.0f / 40320 + a2 * (-1.0f / 3628800)))));
}

/// Concentric map of [0,1)^2 to the unit disk (Shirley, Chiu 1997, "A Low Distortion Map Between
/// Disk and Square").
inline Vec2 sample_concentric_disk(Vec2 u) {
  const float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
  if (ox == 0.0f && oy == 0.0f) return {0, 0};
  constexpr float kPi4 = std::numbers::pi_v<float> / 4.0f;
  // The angle is pi/4 (oy / ox), or pi/2 - pi/4 (ox / oy) with sine and cosine swapped, so only
  // angles in [-pi/4, pi/4] are evaluated. Both cases by selects rather than a branch: which
  // coordinate is larger is as unpredictable as u (the same operations, so the same bits).
  const bool x_major = std::fabs(ox) > std::fabs(oy);
  const float r = x_major ? ox : oy, q = x_major ? oy : ox;
  float s, c;
  sin_cos_quarter(kPi4 * (q / r), s, c);
  const float rc = r * c, rs = r * s;
  return {x_major ? rc : rs, x_major ? rs : rc};
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method); pdf = cos(theta) / pi.
inline Vec3 sample_cosine_hemisphere(Vec2 u) {
  const Vec2 d = sample_concentric_disk(u);
  // std::max (NaN gives 0, as std::fmax would) compiles to one instruction; fmax is a libm call.
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}

/// A sphere enclosing the box `b` (centre and radius; radius 0 for an empty box).
inline void bounding_sphere(const Bounds3& b, Vec3& center, float& radius) {
  if (!(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z)) {
    center = {}, radius = 0.0f;
    return;
  }
  center = (b.lo + b.hi) * 0.5f;
  radius = length(b.hi - center);
}

/// The origin of a ray arriving from direction `w` (unit, pointing away from the scene) at a scene
/// bounded by the sphere (center, radius): a point of the disc of that radius facing w, one radius
/// out along w, uniform for uniform u. The density of origins is 1 / (pi radius^2).
inline Vec3 sample_disc_origin(Vec3 center, float radius, Vec3 w, Vec2 u) {
  const Vec2 d = sample_concentric_disk(u);
  Vec3 t, b;
  orthonormal_basis(w, t, b);
  return center + (w + t * d.x + b * d.y) * radius;
}

/// Power heuristic with exponent 2 (Veach, Guibas 1995, "Optimally Combining Sampling Techniques
/// for Monte Carlo Rendering"): the weight of a sample drawn by the strategy of density f_pdf
/// (times its sample count nf) against the strategy of density g_pdf (times ng).
inline float power_heuristic(float nf, float f_pdf, float ng, float g_pdf) {
  const float f = nf * f_pdf, g = ng * g_pdf;
  if (std::isinf(f * f)) return 1.0f;
  const float sum = f * f + g * g;
  return sum > 0.0f ? f * f / sum : 0.0f;
}

}  // namespace penumbra
