#include "penumbra/render/sampler/sobol_sampler.h"

#if defined(__AVX512F__) && defined(__AVX512BW__) && defined(__GFNI__)
#include <immintrin.h>
#define PENUMBRA_SOBOL_GFNI 1
#endif

#include "penumbra/core/rng.h"
#include "penumbra/render/sampler/low_discrepancy.h"

namespace penumbra {

namespace {
/// The 32-bit golden ratio, the step between pairs before mixing.
constexpr uint32_t kGolden32 = 0x9e3779b9u;
/// The offset of the second coordinate's scramble seeds from the first's (the fraction of
/// sqrt(2)): yk_s = hi_(s + j) only for j = 0x6a09e667 / G mod 2^32, about 2 * 10^9 pairs away.
constexpr uint32_t kSecondKey = 0x6a09e667u;

/// The shuffled index of a pixel sample among spp = 2^log2_spp (log2_spp = -1 otherwise) for a
/// pair's seed; reversed_index is reverse_bits(index << (32 - m)) when spp = 2^m, m > 0.
uint32_t shuffled_index(int log2_spp, uint32_t spp, uint32_t index, uint32_t reversed_index,
                        uint32_t seed) {
  if (log2_spp == 0) return 0;
  if (log2_spp > 0) {
    // A nested uniform scramble permutes the index's m bits among themselves (each bit's flip
    // depends only on the bits above it): owen_scramble(index << shift, seed) >> shift.
    return reverse_bits(laine_karras_permutation(reversed_index, seed)) >> (32 - log2_spp);
  }
  return permutation_element(index, spp, seed);
}

/// Pair d of the pixel sample with hash halves lo_key and hi_key, one value at a time: the
/// definition that the vector batches reproduce.
void pair_value(uint32_t d, uint32_t lo_key, uint32_t hi_key, int log2_spp, uint32_t spp,
                uint32_t index, uint32_t reversed_index, float& x, float& y) {
  const uint32_t lo = mix32(lo_key + d * kGolden32);
  const uint32_t hi = mix32(hi_key + d * kGolden32);
  const uint32_t yk = mix32(hi_key + d * kGolden32 + kSecondKey);
  const uint32_t idx = shuffled_index(log2_spp, spp, index, reversed_index, lo);
  // The values are below 2^24 after the shift, so the signed conversion is exact (and
  // vectorises without AVX-512).
  x = float(int32_t(owen_scrambled_dim0(idx, hi) >> 8)) * 0x1p-24f;
  y = float(int32_t(owen_scrambled_dim1(idx, yk) >> 8)) * 0x1p-24f;
}

#ifdef PENUMBRA_SOBOL_GFNI
/// 16 lanes of 32 bits, in GCC's vector extension (its shifts, products and XORs are lane-wise;
/// the intrinsics of GCC 12 for them warn of an uninitialised operand, GCC bug 105593).
using U32x16 = uint32_t __attribute__((vector_size(64)));
using F32x16 = float __attribute__((vector_size(64)));

/// reverse_bits of 16 lanes: the bits of every byte reversed by one GF(2) affine map (the
/// matrix with ones on the anti-diagonal), then the bytes of every 32-bit lane by a shuffle. Two
/// instructions instead of the ten shifts and masks that the portable version vectorises to.
inline U32x16 reverse_bits(U32x16 x) {
  const __m512i bits =
      _mm512_gf2p8affine_epi64_epi8(__m512i(x), _mm512_set1_epi64(0x8040201008040201ll), 0);
  // Per 128-bit lane, bytes 3 2 1 0, 7 6 5 4, ...; as 32-bit words, little-endian.
  const __m512i bswap = _mm512_set4_epi32(0x0c0d0e0f, 0x08090a0b, 0x04050607, 0x00010203);
  return U32x16(_mm512_shuffle_epi8(bits, bswap));
}
// The overload above hides low_discrepancy.h's (scalar and eight-lane) from sobol_lanes, whose
// eight-lane instantiations (SobolLanes) need them: declared here beside it.
using penumbra::reverse_bits;

#endif

#if defined(PENUMBRA_SOBOL_GFNI) || defined(__AVX2__)
/// The values of K vectors of pairs at once (U: 32-bit lanes; I and F: int32 and float vectors of
/// as many lanes): lane i of vector k is pair d[k][i] of the pixel sample whose keys are lane i
/// of lo[k], hi[k] and reversed[k]. Each lane's seeds, its shuffled index and its two scrambled
/// Sobol' dimensions, as pair_value computes them; `shuffled(k, i, seed)` gives the index when
/// spp is not a power of two. Each step runs for all K vectors before the next, so their chains
/// of dependent products overlap (one vector's chain is about as long as three vectors' work).
/// One body for the 16-lane (AVX-512 with GFNI) and the 8-lane (AVX2) vectors, which differ in
/// reverse_bits.
template <int K, class U, class I, class F, class Shuffled>
void sobol_lanes(const U (&d)[K], const U (&lo)[K], const U (&hi)[K], int log2_spp,
                 const U (&reversed)[K], const Shuffled& shuffled, F (&x)[K], F (&y)[K]) {
  U seed_lo[K], seed_hi[K], seed_y[K], idx[K];
  for (int k = 0; k < K; ++k) {
    seed_lo[k] = mix32(lo[k] + d[k] * kGolden32);
    seed_hi[k] = mix32(hi[k] + d[k] * kGolden32);
    seed_y[k] = mix32(hi[k] + d[k] * kGolden32 + kSecondKey);
  }
  if (log2_spp > 0) {
    for (int k = 0; k < K; ++k)
      idx[k] = reverse_bits(laine_karras_permutation(reversed[k], seed_lo[k])) >>
               uint32_t(32 - log2_spp);
  } else {
    for (int k = 0; k < K; ++k)
      for (int i = 0; i < int(sizeof(U) / 4); ++i) idx[k][i] = shuffled(k, i, seed_lo[k][i]);
  }
  for (int k = 0; k < K; ++k) {
    const U vx = reverse_bits(laine_karras_permutation(idx[k], seed_hi[k]));
    const U vy = reverse_bits(laine_karras_permutation(sobol_dim1_reversed(idx[k]), seed_y[k]));
    // Below 2^24 after the shift: the signed conversion (AVX2 has no unsigned one) is exact.
    x[k] = __builtin_convertvector(I(vx >> 8), F) * 0x1p-24f;
    y[k] = __builtin_convertvector(I(vy >> 8), F) * 0x1p-24f;
  }
}
#endif
}  // namespace

SobolSampler::SobolSampler(int spp, uint64_t seed) : spp_(spp), seed_(seed) {
  for (int m = 0; m < 31; ++m)
    if (spp == (1 << m)) log2_spp_ = m;
}

void SobolSampler::start_pixel_sample(int px, int py, int index) {
  pixel_hash_ = hash_combine(seed_, (uint64_t(uint32_t(py)) << 32) | uint32_t(px));
  index_ = static_cast<uint32_t>(index);
  // The index as the top m bits of a fraction, bit-reversed once here rather than per pair.
  reversed_index_ = log2_spp_ > 0 ? reverse_bits(index_ << (32 - log2_spp_)) : 0;
  dim_ = kFirstPair;
  // No batch yet: slot() finds every pair below 2^31 outside it, also after a resume().
  base_ = dim_ + (1u << 31);
  has_pending_ = false;
}

uint32_t SobolSampler::shuffled(uint32_t seed) const {
  return shuffled_index(log2_spp_, uint32_t(spp_), index_, reversed_index_, seed);
}

void SobolSampler::fill_batch() {
  base_ = dim_;
  // The seeds of the batch's pairs: 32-bit mixes of the pixel hash's halves, which vectorise
  // without emulated 64-bit products (one 64-bit mix per dimension was half of this function's
  // time on AVX2).
  const uint32_t lo_key = uint32_t(pixel_hash_), hi_key = uint32_t(pixel_hash_ >> 32);
  // Per slot the pixel's spp points in a per-pair random order, so pairs do not
  // correlate; the set itself (the first spp points, a (0,m,2)-net when spp = 2^m) is the same in
  // every order.
#if defined(PENUMBRA_SOBOL_GFNI) || defined(__AVX2__)
  const auto shuffled_lane = [this](int, int, uint32_t seed) { return shuffled(seed); };
#endif
#ifdef PENUMBRA_SOBOL_GFNI
  static_assert(kBatch == 16, "one 512-bit register of 32-bit lanes per batch");
  // pair_value for 16 pairs at once, with bit reversals by GFNI: the same values.
  {
    using I32x16 = int32_t __attribute__((vector_size(64)));
    const U32x16 d[1] = {base_ + U32x16{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}};
    const U32x16 lo[1] = {U32x16{} + lo_key}, hi[1] = {U32x16{} + hi_key};
    const U32x16 rev[1] = {U32x16{} + reversed_index_};
    F32x16 x[1], y[1];
    sobol_lanes<1, U32x16, I32x16, F32x16>(d, lo, hi, log2_spp_, rev, shuffled_lane, x, y);
    __builtin_memcpy(x_, x, sizeof x_);
    __builtin_memcpy(y_, y, sizeof y_);
    return;
  }
#elif defined(__AVX2__)
  static_assert(kBatch == 16, "two 256-bit registers of 32-bit lanes per batch");
  // pair_value for 16 pairs at once, with bit reversals by nibble lookups: the same values.
  {
    using F32x8 = float __attribute__((vector_size(32)));
    using I32x8 = int32_t __attribute__((vector_size(32)));
    const U32x8 first = base_ + U32x8{0, 1, 2, 3, 4, 5, 6, 7};
    const U32x8 d[2] = {first, first + 8u};
    const U32x8 lo[2] = {U32x8{} + lo_key, U32x8{} + lo_key};
    const U32x8 hi[2] = {U32x8{} + hi_key, U32x8{} + hi_key};
    const U32x8 rev[2] = {U32x8{} + reversed_index_, U32x8{} + reversed_index_};
    F32x8 x[2], y[2];
    sobol_lanes<2, U32x8, I32x8, F32x8>(d, lo, hi, log2_spp_, rev, shuffled_lane, x, y);
    __builtin_memcpy(x_, x, sizeof x_);
    __builtin_memcpy(y_, y, sizeof y_);
    return;
  }
#endif
  for (uint32_t k = 0; k < kBatch; ++k)
    pair_value(base_ + k, lo_key, hi_key, log2_spp_, uint32_t(spp_), index_, reversed_index_, x_[k],
               y_[k]);
}

using lanes::F8;
using lanes::U8;

void SobolLanes::compute(U8 lane, U8 pair, F8& x, F8& y) const {
  const U8 lo = __builtin_shuffle(load(lo_), lane), hi = __builtin_shuffle(load(hi_), lane);
  const U8 rev = __builtin_shuffle(load(reversed_), lane);
#if defined(__AVX2__)
  using I32x8 = int32_t __attribute__((vector_size(32)));
  const U8 d[1] = {pair}, l[1] = {lo}, h[1] = {hi}, r[1] = {rev};
  F8 xs[1], ys[1];
  const auto shuffled_lane = [&](int, int i, uint32_t seed) {
    return shuffled_index(log2_spp_, spp_, index_[lane[i] % kWidth], reversed_[lane[i] % kWidth],
                          seed);
  };
  sobol_lanes<1, U8, I32x8, F8>(d, l, h, log2_spp_, r, shuffled_lane, xs, ys);
  x = xs[0], y = ys[0];
#else
  for (int i = 0; i < kWidth; ++i) {
    float a, b;
    pair_value(pair[i], lo[i], hi[i], log2_spp_, spp_, index_[lane[i] % kWidth], rev[i], a, b);
    x[i] = a, y[i] = b;
  }
#endif
}

void SobolLanes::compute3(U8 first, F8 (&x)[3], F8 (&y)[3]) const {
  const U8 lo = load(lo_), hi = load(hi_), rev = load(reversed_);
#if defined(__AVX2__)
  using I32x8 = int32_t __attribute__((vector_size(32)));
  const U8 d[3] = {first, first + 1u, first + 2u}, l[3] = {lo, lo, lo}, h[3] = {hi, hi, hi};
  const U8 r[3] = {rev, rev, rev};
  const auto shuffled_lane = [&](int, int i, uint32_t seed) {
    return shuffled_index(log2_spp_, spp_, index_[i], reversed_[i], seed);
  };
  sobol_lanes<3, U8, I32x8, F8>(d, l, h, log2_spp_, r, shuffled_lane, x, y);
#else
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < kWidth; ++i) {
      float a, b;
      pair_value(first[i] + uint32_t(j), lo[i], hi[i], log2_spp_, spp_, index_[i], rev[i], a, b);
      x[j][i] = a, y[j][i] = b;
    }
#endif
}

}  // namespace penumbra
