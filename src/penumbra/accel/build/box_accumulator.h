#pragma once
/// A box grown one primitive box at a time, with a branch-free surface area: the inner loop of
/// the SAH sweeps (binned and full).
#include <algorithm>

#include "penumbra/core/bounds.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace penumbra {

/// A growing box of 4-float vectors (the 4th lane ignored) whose area is 0 while it is empty.
/// `l` and `h` point at 16-byte aligned (x, y, z, any) corners, as in PrimRef and the bins.
struct BoxAccumulator {
#if defined(__SSE2__)
  __m128 lo = _mm_set1_ps(kInfinity), hi = _mm_set1_ps(-kInfinity);
  /// Extends the box by [l, h].
  void add(const float* l, const float* h) {
    lo = _mm_min_ps(lo, _mm_load_ps(l));
    hi = _mm_max_ps(hi, _mm_load_ps(h));
  }
  /// Surface area (0 while empty).
  float area() const {
    alignas(16) float d[4];
    _mm_store_ps(d, _mm_max_ps(_mm_sub_ps(hi, lo), _mm_setzero_ps()));
    return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
  }
  /// The box as Bounds3.
  Bounds3 bounds() const {
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    Bounds3 b;
    b.lo = {l[0], l[1], l[2]};
    b.hi = {h[0], h[1], h[2]};
    return b;
  }
#else
  float lo[3] = {kInfinity, kInfinity, kInfinity}, hi[3] = {-kInfinity, -kInfinity, -kInfinity};
  /// Extends the box by [l, h].
  void add(const float* l, const float* h) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], l[k]), hi[k] = std::max(hi[k], h[k]);
  }
  /// Surface area (0 while empty).
  float area() const {
    float d[3];
    for (int k = 0; k < 3; ++k) d[k] = std::max(hi[k] - lo[k], 0.0f);
    return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
  }
  /// The box as Bounds3.
  Bounds3 bounds() const {
    Bounds3 b;
    b.lo = {lo[0], lo[1], lo[2]};
    b.hi = {hi[0], hi[1], hi[2]};
    return b;
  }
#endif
};

}  // namespace penumbra
