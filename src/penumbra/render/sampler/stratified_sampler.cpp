#include "penumbra/render/sampler/stratified_sampler.h"

#include <cmath>

#include "penumbra/render/sampler/low_discrepancy.h"

namespace penumbra {

StratifiedSampler::StratifiedSampler(int spp, uint64_t seed, bool jitter)
    : spp_(spp), seed_(seed), jitter_(jitter) {
  // The factorisation nx * ny = spp with nx the largest divisor not above sqrt(spp).
  nx_ = static_cast<int>(std::sqrt(double(spp)));
  while (spp % nx_ != 0) --nx_;
  ny_ = spp / nx_;
}

void StratifiedSampler::start_pixel_sample(int px, int py, int index) {
  pixel_ = (uint64_t(uint32_t(py)) << 32) | uint32_t(px);
  index_ = index;
  dim_ = 0;
  rng_.set(hash_combine(seed_ ^ 0x5851f42d4c957f2dull, pixel_), hash_combine(pixel_, uint64_t(index)));
}

uint32_t StratifiedSampler::dimension_seed() {
  return static_cast<uint32_t>(hash_combine(hash_combine(seed_, pixel_), dim_++));
}

float StratifiedSampler::offset() { return jitter_ ? rng_.next_float() : 0.5f; }

Vec2 StratifiedSampler::get_pixel_2d() {
  // Sample i of the pixel takes stratum i: row-major over nx x ny.
  const int sx = index_ % nx_, sy = index_ / nx_;
  ++dim_, ++dim_;
  const float ox = offset(), oy = offset();
  return {(float(sx) + ox) / float(nx_), (float(sy) + oy) / float(ny_)};
}

float StratifiedSampler::get_1d() {
  const uint32_t s = permutation_element(uint32_t(index_), uint32_t(spp_), dimension_seed());
  const float v = (float(s) + offset()) / float(spp_);
  return v < 1.0f ? v : 0x1.fffffep-1f;
}

Vec2 StratifiedSampler::get_2d() {
  const uint32_t s = permutation_element(uint32_t(index_), uint32_t(spp_), dimension_seed());
  ++dim_;
  const int sx = int(s) % nx_, sy = int(s) / nx_;
  const float ox = offset(), oy = offset();
  const float x = (float(sx) + ox) / float(nx_), y = (float(sy) + oy) / float(ny_);
  return {x < 1.0f ? x : 0x1.fffffep-1f, y < 1.0f ? y : 0x1.fffffep-1f};
}

}  // namespace penumbra
