#pragma once
/// A minimal vector of W floats for the wide BVH: SSE for W = 4, AVX for W = 8 (and 16, as two
/// registers), plain arrays otherwise. Only what the box tests need: load, broadcast, arithmetic,
/// min/max, compare.
#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace penumbra {

/// W floats; min and max return their second argument when the first is NaN, as the SSE and AVX
/// instructions do, so a NaN term never replaces a running bound.
template <int W>
struct FloatW {
  float v[W];

  /// W floats from `p` (aligned to the vector size).
  static FloatW load(const float* p) {
    FloatW r;
    for (int i = 0; i < W; ++i) r.v[i] = p[i];
    return r;
  }
  /// x in every lane.
  static FloatW broadcast(float x) {
    FloatW r;
    for (int i = 0; i < W; ++i) r.v[i] = x;
    return r;
  }
  /// W unsigned bytes from `p`, converted exactly.
  static FloatW from_u8(const uint8_t* p) {
    FloatW r;
    for (int i = 0; i < W; ++i) r.v[i] = float(p[i]);
    return r;
  }
  friend FloatW operator+(FloatW a, FloatW b) {
    for (int i = 0; i < W; ++i) a.v[i] += b.v[i];
    return a;
  }
  friend FloatW operator-(FloatW a, FloatW b) {
    for (int i = 0; i < W; ++i) a.v[i] -= b.v[i];
    return a;
  }
  friend FloatW operator*(FloatW a, FloatW b) {
    for (int i = 0; i < W; ++i) a.v[i] *= b.v[i];
    return a;
  }
  friend FloatW max(FloatW a, FloatW b) {
    for (int i = 0; i < W; ++i) a.v[i] = a.v[i] > b.v[i] ? a.v[i] : b.v[i];
    return a;
  }
  friend FloatW min(FloatW a, FloatW b) {
    for (int i = 0; i < W; ++i) a.v[i] = a.v[i] < b.v[i] ? a.v[i] : b.v[i];
    return a;
  }
  /// Bit i set where a[i] <= b[i].
  friend unsigned mask_le(FloatW a, FloatW b) {
    unsigned m = 0;
    for (int i = 0; i < W; ++i) m |= unsigned(a.v[i] <= b.v[i]) << i;
    return m;
  }
  /// Writes the lanes to `p` (aligned to the vector size).
  void store(float* p) const {
    for (int i = 0; i < W; ++i) p[i] = v[i];
  }
};

#if defined(__SSE2__)
/// Four lanes in an SSE register.
template <>
struct FloatW<4> {
  __m128 v;
  static FloatW load(const float* p) { return {_mm_load_ps(p)}; }
  static FloatW broadcast(float x) { return {_mm_set1_ps(x)}; }
  friend FloatW operator-(FloatW a, FloatW b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend FloatW operator*(FloatW a, FloatW b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend FloatW max(FloatW a, FloatW b) { return {_mm_max_ps(a.v, b.v)}; }
  friend FloatW min(FloatW a, FloatW b) { return {_mm_min_ps(a.v, b.v)}; }
  friend unsigned mask_le(FloatW a, FloatW b) {
    return unsigned(_mm_movemask_ps(_mm_cmple_ps(a.v, b.v)));
  }
  void store(float* p) const { _mm_store_ps(p, v); }
};
#endif

#if defined(__AVX__)
/// Eight lanes in an AVX register.
template <>
struct FloatW<8> {
  __m256 v;
  static FloatW load(const float* p) { return {_mm256_load_ps(p)}; }
  static FloatW broadcast(float x) { return {_mm256_set1_ps(x)}; }
  static FloatW from_u8(const uint8_t* p) {
#if defined(__AVX2__)
    const __m128i bytes = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));
    return {_mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(bytes))};
#else
    return {_mm256_setr_ps(float(p[0]), float(p[1]), float(p[2]), float(p[3]), float(p[4]),
                           float(p[5]), float(p[6]), float(p[7]))};
#endif
  }
  friend FloatW operator+(FloatW a, FloatW b) { return {_mm256_add_ps(a.v, b.v)}; }
  friend FloatW operator-(FloatW a, FloatW b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend FloatW operator*(FloatW a, FloatW b) { return {_mm256_mul_ps(a.v, b.v)}; }
  friend FloatW max(FloatW a, FloatW b) { return {_mm256_max_ps(a.v, b.v)}; }
  friend FloatW min(FloatW a, FloatW b) { return {_mm256_min_ps(a.v, b.v)}; }
  friend unsigned mask_le(FloatW a, FloatW b) {
    return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)));
  }
  void store(float* p) const { _mm256_store_ps(p, v); }
};
#endif

#if defined(__AVX__)
/// Sixteen lanes as two AVX registers (the 16-wide BVH), also where AVX-512 is available: with
/// one 512-bit register per row the Intel Xeon measured ran every ray set 2-6 % slower (most
/// likely as 512-bit arithmetic lowers the core's clock; docs/accel.md, "2026-12-06, twelfth
/// session").
template <>
struct FloatW<16> {
  __m256 lo, hi;  ///< lanes 0-7 and 8-15
  static FloatW load(const float* p) { return {_mm256_load_ps(p), _mm256_load_ps(p + 8)}; }
  static FloatW broadcast(float x) { return {_mm256_set1_ps(x), _mm256_set1_ps(x)}; }
  friend FloatW operator+(FloatW a, FloatW b) {
    return {_mm256_add_ps(a.lo, b.lo), _mm256_add_ps(a.hi, b.hi)};
  }
  friend FloatW operator-(FloatW a, FloatW b) {
    return {_mm256_sub_ps(a.lo, b.lo), _mm256_sub_ps(a.hi, b.hi)};
  }
  friend FloatW operator*(FloatW a, FloatW b) {
    return {_mm256_mul_ps(a.lo, b.lo), _mm256_mul_ps(a.hi, b.hi)};
  }
  friend FloatW max(FloatW a, FloatW b) {
    return {_mm256_max_ps(a.lo, b.lo), _mm256_max_ps(a.hi, b.hi)};
  }
  friend FloatW min(FloatW a, FloatW b) {
    return {_mm256_min_ps(a.lo, b.lo), _mm256_min_ps(a.hi, b.hi)};
  }
  friend unsigned mask_le(FloatW a, FloatW b) {
    return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(a.lo, b.lo, _CMP_LE_OQ))) |
           unsigned(_mm256_movemask_ps(_mm256_cmp_ps(a.hi, b.hi, _CMP_LE_OQ))) << 8;
  }
  void store(float* p) const {
    _mm256_store_ps(p, lo);
    _mm256_store_ps(p + 8, hi);
  }
};
#endif

}  // namespace penumbra
