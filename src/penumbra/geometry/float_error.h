#pragma once
/// Floating-point error bounds and robust spawning of secondary rays.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "penumbra/core/vec.h"

namespace penumbra {

/// Unit roundoff of float (2^-24).
inline constexpr float kMachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;

/// Bound on the relative error of n successive float operations, n u / (1 - n u) (Higham 2002,
/// "Accuracy and Stability of Numerical Algorithms", as used by pbrt-v3 section 3.9).
constexpr float gamma(int n) { return (n * kMachineEpsilon) / (1 - n * kMachineEpsilon); }

/// The next float above v: std::nextafter(v, +infinity) without the library call (pbrt-v4's
/// NextFloatUp, on the bit pattern); +infinity and NaN come back unchanged.
inline float next_float_up(float v) {
  if (!(v < std::numeric_limits<float>::infinity())) return v;
  if (v == 0.0f) v = 0.0f;  // -0 becomes +0, whose successor is the smallest denormal
  const auto bits = std::bit_cast<uint32_t>(v);
  return std::bit_cast<float>(v >= 0.0f ? bits + 1 : bits - 1);
}
/// The next float below v: std::nextafter(v, -infinity); -infinity and NaN come back unchanged.
inline float next_float_down(float v) {
  if (!(v > -std::numeric_limits<float>::infinity())) return v;
  if (v == 0.0f) v = -0.0f;
  const auto bits = std::bit_cast<uint32_t>(v);
  return std::bit_cast<float>(v > 0.0f ? bits - 1 : bits + 1);
}

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
    if (offset[i] > 0.0f) po[i] = next_float_up(po[i]);
    else if (offset[i] < 0.0f) po[i] = next_float_down(po[i]);
  }
  return po;
}

}  // namespace penumbra
