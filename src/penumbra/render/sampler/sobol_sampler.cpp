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

#endif

#if defined(PENUMBRA_SOBOL_GFNI) || defined(__AVX2__)
/// The batch's values for the pairs in the lanes of `d` (U: 32-bit lanes; I and F: int32
/// and float vectors of as many lanes), written to x and y: each lane's seeds, its shuffled index
/// and its two scrambled Sobol' dimensions, as the scalar loop of fill_batch computes them.
/// `shuffled(seed)` gives the index when spp is not a power of two. One body for the 16-lane
/// (AVX-512 with GFNI) and the 8-lane (AVX2) batches, which differ in reverse_bits.
template <class U, class I, class F, class Shuffled>
void sobol_lanes(U d, uint32_t lo_key, uint32_t hi_key, int log2_spp, uint32_t reversed_index,
                 const Shuffled& shuffled, float* x, float* y) {
  const U seed_lo = mix32(lo_key + d * kGolden32);
  const U seed_hi = mix32(hi_key + d * kGolden32);
  const U seed_y = mix32(hi_key + d * kGolden32 + kSecondKey);
  U idx;
  if (log2_spp > 0) {
    idx = reverse_bits(laine_karras_permutation(U{} + reversed_index, seed_lo)) >>
          uint32_t(32 - log2_spp);
  } else {
    for (int k = 0; k < int(sizeof(U) / 4); ++k) idx[k] = shuffled(seed_lo[k]);
  }
  const U vx = reverse_bits(laine_karras_permutation(idx, seed_hi));
  const U vy = reverse_bits(laine_karras_permutation(sobol_dim1_reversed(idx), seed_y));
  // Below 2^24 after the shift: the signed conversion (AVX2 has no unsigned one) is exact.
  const F fx = __builtin_convertvector(I(vx >> 8), F) * 0x1p-24f;
  const F fy = __builtin_convertvector(I(vy >> 8), F) * 0x1p-24f;
  __builtin_memcpy(x, &fx, sizeof fx);
  __builtin_memcpy(y, &fy, sizeof fy);
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
  dim_ = 1;
  base_ = dim_ + kBatch;  // no batch yet
  has_pending_ = false;
}

uint32_t SobolSampler::shuffled(uint32_t seed) const {
  if (log2_spp_ == 0) return 0;
  if (log2_spp_ > 0) {
    // A nested uniform scramble permutes the index's m bits among themselves (each bit's flip
    // depends only on the bits above it): owen_scramble(index << shift, seed) >> shift.
    return reverse_bits(laine_karras_permutation(reversed_index_, seed)) >> (32 - log2_spp_);
  }
  return permutation_element(index_, uint32_t(spp_), seed);
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
  const auto shuffled_lane = [this](uint32_t seed) { return shuffled(seed); };
#endif
#ifdef PENUMBRA_SOBOL_GFNI
  static_assert(kBatch == 16, "one 512-bit register of 32-bit lanes per batch");
  // The scalar loops below, 16 lanes at once, with bit reversals by GFNI: the same values.
  using I32x16 = int32_t __attribute__((vector_size(64)));
  sobol_lanes<U32x16, I32x16, F32x16>(
      base_ + U32x16{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}, lo_key, hi_key,
      log2_spp_, reversed_index_, shuffled_lane, x_, y_);
  return;
#elif defined(__AVX2__)
  static_assert(kBatch % 8 == 0, "whole 256-bit registers of 32-bit lanes per batch");
  // The scalar loops below, 8 lanes at once, with bit reversals by nibble lookups: the same
  // values.
  using F32x8 = float __attribute__((vector_size(32)));
  using I32x8 = int32_t __attribute__((vector_size(32)));
  for (uint32_t half = 0; half < kBatch; half += 8)
    sobol_lanes<U32x8, I32x8, F32x8>(base_ + half + U32x8{0, 1, 2, 3, 4, 5, 6, 7}, lo_key, hi_key,
                                     log2_spp_, reversed_index_, shuffled_lane, x_ + half,
                                     y_ + half);
  return;
#endif
  uint32_t lo[kBatch], hi[kBatch], yk[kBatch], idx[kBatch];
  for (uint32_t k = 0; k < kBatch; ++k) lo[k] = mix32(lo_key + (base_ + k) * kGolden32);
  for (uint32_t k = 0; k < kBatch; ++k) hi[k] = mix32(hi_key + (base_ + k) * kGolden32);
  for (uint32_t k = 0; k < kBatch; ++k)
    yk[k] = mix32(hi_key + (base_ + k) * kGolden32 + kSecondKey);
  if (log2_spp_ > 0) {
    const uint32_t shift = 32 - uint32_t(log2_spp_);
    for (uint32_t k = 0; k < kBatch; ++k)
      idx[k] = reverse_bits(laine_karras_permutation(reversed_index_, lo[k])) >> shift;
  } else {
    for (uint32_t k = 0; k < kBatch; ++k) idx[k] = shuffled(lo[k]);
  }
  // Both Sobol' dimensions of each slot; the values are below 2^24 after the shift, so the
  // signed conversion is exact (and vectorises without AVX-512).
  for (uint32_t k = 0; k < kBatch; ++k) {
    const uint32_t vx = owen_scrambled_dim0(idx[k], hi[k]);
    const uint32_t vy = owen_scrambled_dim1(idx[k], yk[k]);
    x_[k] = float(int32_t(vx >> 8)) * 0x1p-24f;
    y_[k] = float(int32_t(vy >> 8)) * 0x1p-24f;
  }
}

}  // namespace penumbra
