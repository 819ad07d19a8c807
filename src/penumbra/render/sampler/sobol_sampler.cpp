#include "penumbra/render/sampler/sobol_sampler.h"

#include "penumbra/core/rng.h"
#include "penumbra/render/sampler/low_discrepancy.h"

namespace penumbra {

SobolSampler::SobolSampler(int spp, uint64_t seed) : spp_(spp), seed_(seed) {
  for (int m = 0; m < 31; ++m)
    if (spp == (1 << m)) log2_spp_ = m;
}

void SobolSampler::start_pixel_sample(int px, int py, int index) {
  pixel_hash_ = hash_combine(seed_, (uint64_t(uint32_t(py)) << 32) | uint32_t(px));
  index_ = static_cast<uint32_t>(index);
  dim_ = 0;
}

uint64_t SobolSampler::next_hash() {
  return mix64(pixel_hash_ + uint64_t(++dim_) * 0x9e3779b97f4a7c15ull);
}

uint32_t SobolSampler::shuffled(uint32_t seed) const {
  if (log2_spp_ == 0) return 0;
  if (log2_spp_ > 0) {
    // The index as the top m bits of a fraction: a nested uniform scramble permutes those bits
    // among themselves (each bit's flip depends only on the bits above it).
    const int shift = 32 - log2_spp_;
    return owen_scramble(index_ << shift, seed) >> shift;
  }
  return permutation_element(index_, uint32_t(spp_), seed);
}

float SobolSampler::get_1d() {
  // The pixel's spp points in a per-dimension random order, so dimensions do not correlate; the
  // set itself (the first spp points, a (0,m,2)-net when spp = 2^m) is the same in every order.
  const uint64_t h = next_hash();
  const uint32_t i = shuffled(uint32_t(h));
  return fraction_to_float(owen_scrambled_dim0(i, uint32_t(h >> 32)));
}

Vec2 SobolSampler::get_2d() {
  const uint64_t h = next_hash(), g = next_hash();
  const uint32_t i = shuffled(uint32_t(h));
  return {fraction_to_float(owen_scrambled_dim0(i, uint32_t(h >> 32))),
          fraction_to_float(owen_scramble(sobol_dim1(i), uint32_t(g)))};
}

}  // namespace penumbra
