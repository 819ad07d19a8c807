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
inline bool traceable(const Ray& r) {
  return std::isfinite(r.o.x) && std::isfinite(r.o.y) && std::isfinite(r.o.z) &&
         std::isfinite(r.d.x) && std::isfinite(r.d.y) && std::isfinite(r.d.z) &&
         (r.d.x != 0.0f || r.d.y != 0.0f || r.d.z != 0.0f) && r.tmin <= r.tmax;
}

}  // namespace penumbra
