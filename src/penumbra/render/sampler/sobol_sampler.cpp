#include "penumbra/render/sampler/sobol_sampler.h"

#include "penumbra/core/rng.h"
#include "penumbra/render/sampler/low_discrepancy.h"

namespace penumbra {

void SobolSampler::start_pixel_sample(int px, int py, int index) {
  pixel_ = (uint64_t(uint32_t(py)) << 32) | uint32_t(px);
  index_ = static_cast<uint32_t>(index);
  dim_ = 0;
}

uint32_t SobolSampler::next_seed() {
  return static_cast<uint32_t>(hash_combine(hash_combine(seed_, pixel_), dim_++));
}

float SobolSampler::get_1d() {
  // The pixel's spp points in a per-dimension random order, so dimensions do not correlate; the
  // set itself (the first spp points, a (0,m,2)-net when spp = 2^m) is the same in every order.
  const uint32_t i = permutation_element(index_, uint32_t(spp_), next_seed());
  return fraction_to_float(owen_scramble(sobol_dim0(i), next_seed()));
}

Vec2 SobolSampler::get_2d() {
  const uint32_t i = permutation_element(index_, uint32_t(spp_), next_seed());
  const uint32_t sx = next_seed(), sy = next_seed();
  return {fraction_to_float(owen_scramble(sobol_dim0(i), sx)),
          fraction_to_float(owen_scramble(sobol_dim1(i), sy))};
}

}  // namespace penumbra
