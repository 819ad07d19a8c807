#pragma once
/// Floating-point error bounds and robust spawning of secondary rays.
#include <cmath>
#include <limits>

#include "penumbra/core/vec.h"

namespace penumbra {

/// Unit roundoff of float (2^-24).
inline constexpr float kMachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;

/// Bound on the relative error of n successive float operations, n u / (1 - n u) (Higham 2002,
/// "Accuracy and Stability of Numerical Algorithms", as used by pbrt-v3 section 3.9).
constexpr float gamma(int n) { return (n * kMachineEpsilon) / (1 - n * kMachineEpsilon); }

/// Origin for a ray leaving a surface point `p` (absolute error bound `p_error` per axis, geometric
/// normal `n`) in direction `w`: moved along the normal, to the side of `w`, just past the error
/// box, then rounded one ulp further away so the new ray cannot re-hit the surface it leaves
/// (Pharr, Jakob, Humphreys, "Physically Based Rendering", 3rd ed., section 3.9.5).
inline Vec3 offset_ray_origin(Vec3 p, Vec3 p_error, Vec3 n, Vec3 w) {
  const float d = dot(abs(n), p_error);
  Vec3 offset = n * d;
  if (dot(w, n) < 0.0f) offset = -offset;
  Vec3 po = p + offset;
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0.0f) po[i] = std::nextafter(po[i], std::numeric_limits<float>::infinity());
    else if (offset[i] < 0.0f) po[i] = std::nextafter(po[i], -std::numeric_limits<float>::infinity());
  }
  return po;
}

}  // namespace penumbra
