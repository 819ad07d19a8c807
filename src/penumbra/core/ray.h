#pragma once
/// A ray o + t d with a parametric interval [tmin, tmax] and a time (for motion blur).
#include <cmath>
#include <limits>

#include "penumbra/core/vec.h"

namespace penumbra {

/// Infinity for ray intervals.
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

/// A ray; `tmax` shrinks as closer hits are found. `time` lies in the camera's shutter interval.
struct Ray {
  Vec3 o;
  Vec3 d;
  float tmin = 0.0f;
  float tmax = kInfinity;
  float time = 0.0f;

  /// The point at parameter t.
  constexpr Vec3 at(float t) const { return o + d * t; }
};

/// True when `r` can be traced: a finite origin, a finite non-zero direction and an interval
/// that is not NaN and not empty. Every structure answers "no hit" for any other ray before its
/// traversal starts, so a NaN from a broken shader or an overflowing scene never reaches a
/// traversal loop (where a NaN slab test passes every box).
/// One branch for the whole test: x - x is 0 exactly when x is finite (NaN for an infinity or
/// a NaN), so a sum of six such differences is 0 exactly when all six are; the rest combine as
/// bits.
inline bool traceable(const Ray& r) {
  const float finite = ((r.o.x - r.o.x) + (r.o.y - r.o.y)) + ((r.o.z - r.o.z) + (r.d.x - r.d.x)) +
                       ((r.d.y - r.d.y) + (r.d.z - r.d.z));
  const bool nonzero = (r.d.x != 0.0f) | (r.d.y != 0.0f) | (r.d.z != 0.0f);
  return (finite == 0.0f) & nonzero & (r.tmin <= r.tmax);
}

}  // namespace penumbra
