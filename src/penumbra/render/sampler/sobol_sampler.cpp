#include "penumbra/render/sampler/sobol_sampler.h"

#include "penumbra/core/rng.h"
#include "penumbra/render/sampler/low_discrepancy.h"

namespace penumbra {

namespace {
constexpr uint64_t kGolden = 0x9e3779b97f4a7c15ull;
}  // namespace

SobolSampler::SobolSampler(int spp, uint64_t seed) : spp_(spp), seed_(seed) {
  for (int m = 0; m < 31; ++m)
    if (spp == (1 << m)) log2_spp_ = m;
}

void SobolSampler::start_pixel_sample(int px, int py, int index) {
  pixel_hash_ = hash_combine(seed_, (uint64_t(uint32_t(py)) << 32) | uint32_t(px));
  index_ = static_cast<uint32_t>(index);
  // The index as the top m bits of a fraction, bit-reversed once here rather than per dimension.
  reversed_index_ = log2_spp_ > 0 ? reverse_bits(index_ << (32 - log2_spp_)) : 0;
  dim_ = 1;
  base_ = dim_ + kBatch;  // no batch yet
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
  // The hashes of the batch's dimensions and of the one after (the last slot's y needs it).
  uint64_t h[kBatch + 1];
  for (uint32_t k = 0; k <= kBatch; ++k) h[k] = mix64(pixel_hash_ + uint64_t(base_ + k) * kGolden);
  // Per slot the pixel's spp points in a per-dimension random order, so dimensions do not
  // correlate; the set itself (the first spp points, a (0,m,2)-net when spp = 2^m) is the same in
  // every order.
  uint32_t idx[kBatch];
  if (log2_spp_ > 0) {
    const uint32_t shift = 32 - uint32_t(log2_spp_);
    for (uint32_t k = 0; k < kBatch; ++k)
      idx[k] = reverse_bits(laine_karras_permutation(reversed_index_, uint32_t(h[k]))) >> shift;
  } else {
    for (uint32_t k = 0; k < kBatch; ++k) idx[k] = shuffled(uint32_t(h[k]));
  }
  // Both Sobol' dimensions of each slot; the values are below 2^24 after the shift, so the
  // signed conversion is exact (and vectorises without AVX-512).
  for (uint32_t k = 0; k < kBatch; ++k) {
    const uint32_t vx = owen_scrambled_dim0(idx[k], uint32_t(h[k] >> 32));
    const uint32_t vy = owen_scrambled_dim1(idx[k], uint32_t(h[k + 1]));
    x_[k] = float(int32_t(vx >> 8)) * 0x1p-24f;
    y_[k] = float(int32_t(vy >> 8)) * 0x1p-24f;
  }
}

}  // namespace penumbra
