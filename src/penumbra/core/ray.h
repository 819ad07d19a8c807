#pragma once
/// A ray o + t d with a parametric interval [tmin, tmax] and a time (for motion blur).
#include <cmath>
#include <cstddef>
#include <limits>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

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
#if defined(__SSE2__)
  // The same tests on two vectors, (o.x, o.y, o.z, d.x) and (d.x, d.y, d.z, tmin): a dozen
  // instructions instead of the forty that the scalar form compiles to (paid by every ray).
  static_assert(offsetof(Ray, d) == 12 && offsetof(Ray, tmin) == 24);
  const char* bytes = reinterpret_cast<const char*>(&r);
  const __m128 a = _mm_loadu_ps(reinterpret_cast<const float*>(bytes));
  const __m128 b = _mm_loadu_ps(reinterpret_cast<const float*>(bytes + 12));
  const __m128 zero = _mm_setzero_ps();
  const int finite_a = _mm_movemask_ps(_mm_cmpeq_ps(_mm_sub_ps(a, a), zero));
  const int finite_b = _mm_movemask_ps(_mm_cmpeq_ps(_mm_sub_ps(b, b), zero));
  const int nonzero = _mm_movemask_ps(_mm_cmpneq_ps(b, zero));
  return (finite_a == 15) & ((finite_b & 7) == 7) & ((nonzero & 7) != 0) & (r.tmin <= r.tmax);
#else
  const float finite = ((r.o.x - r.o.x) + (r.o.y - r.o.y)) + ((r.o.z - r.o.z) + (r.d.x - r.d.x)) +
                       ((r.d.y - r.d.y) + (r.d.z - r.d.z));
  const bool nonzero = (r.d.x != 0.0f) | (r.d.y != 0.0f) | (r.d.z != 0.0f);
  return (finite == 0.0f) & nonzero & (r.tmin <= r.tmax);
#endif
}

}  // namespace penumbra
