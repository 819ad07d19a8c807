#pragma once
/// Uniform random samples, independent between dimensions.
#include "penumbra/core/rng.h"
#include "penumbra/render/sampler/sampler.h"

namespace penumbra {

/// Uniform random sampling: each (pixel, sample) gets its own PCG32 stream derived by hashing
/// (seed, pixel, sample index), so values never depend on scheduling.
class IndependentSampler final : public Sampler {
 public:
  IndependentSampler(int spp, uint64_t seed) : spp_(spp), seed_(seed) {}
  int samples_per_pixel() const override { return spp_; }
  void start_pixel_sample(int px, int py, int index) override {
    const uint64_t pixel = (uint64_t(uint32_t(py)) << 32) | uint32_t(px);
    rng_.set(hash_combine(seed_, pixel), hash_combine(pixel, uint64_t(index)));
  }
  float get_1d() override { return rng_.next_float(); }
  Vec2 get_2d() override {
    const float a = rng_.next_float();
    return {a, rng_.next_float()};
  }
  std::unique_ptr<Sampler> clone() const override {
    return std::make_unique<IndependentSampler>(*this);
  }

 private:
  int spp_;
  uint64_t seed_;
  Pcg32 rng_;
};

}  // namespace penumbra
