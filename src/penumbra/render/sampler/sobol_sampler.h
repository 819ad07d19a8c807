#pragma once
/// A low-discrepancy sampler: the Owen-scrambled (0,2)-sequence, padded across dimensions.
#include "penumbra/render/sampler/sampler.h"

namespace penumbra {

/// Each pair of dimensions takes the first spp points of the (0,2)-sequence (the first two Sobol'
/// dimensions) in a random order and Owen-scrambled, both chosen by hashes of (seed, pixel,
/// dimension) ("padding", Kollig and Keller 2002; scrambling by Burley 2020). With spp = 2^m the
/// points of a pixel form a (0,m,2)-net in each 2D projection: one point in every elementary
/// interval of area 1/spp.
class SobolSampler final : public Sampler {
 public:
  SobolSampler(int spp, uint64_t seed) : spp_(spp), seed_(seed) {}
  int samples_per_pixel() const override { return spp_; }
  void start_pixel_sample(int px, int py, int index) override;
  float get_1d() override;
  Vec2 get_2d() override;
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<SobolSampler>(*this); }

 private:
  uint32_t next_seed();

  int spp_;
  uint64_t seed_;
  uint64_t pixel_ = 0;
  uint32_t index_ = 0;
  uint32_t dim_ = 0;
};

}  // namespace penumbra
