#pragma once
/// Warping uniform samples to directions and points.
#include <cmath>
#include <numbers>

#include "penumbra/core/vec.h"
#include "penumbra/geometry/sphere_direction.h"  // sample_uniform_sphere

namespace penumbra {

/// Concentric map of [0,1)^2 to the unit disk (Shirley, Chiu 1997, "A Low Distortion Map Between
/// Disk and Square").
inline Vec2 sample_concentric_disk(Vec2 u) {
  const float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
  if (ox == 0.0f && oy == 0.0f) return {0, 0};
  constexpr float kPi4 = std::numbers::pi_v<float> / 4.0f;
  float r, theta;
  if (std::fabs(ox) > std::fabs(oy)) r = ox, theta = kPi4 * (oy / ox);
  else r = oy, theta = 2.0f * kPi4 - kPi4 * (ox / oy);
  return {r * std::cos(theta), r * std::sin(theta)};
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method); pdf = cos(theta) / pi.
inline Vec3 sample_cosine_hemisphere(Vec2 u) {
  const Vec2 d = sample_concentric_disk(u);
  const float z = std::sqrt(std::fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}

}  // namespace penumbra
