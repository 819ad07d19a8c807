#pragma once
/// A ray o + t d with a parametric interval [tmin, tmax] and a time (for motion blur).
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

}  // namespace penumbra
