#pragma once
/// A low-discrepancy sampler: the Owen-scrambled (0,2)-sequence, padded across dimensions.
#include "penumbra/render/sampler/sampler.h"

namespace penumbra {

/// Each pair of dimensions takes the first spp points of the (0,2)-sequence (the first two Sobol'
/// dimensions) in a random order and Owen-scrambled, both chosen by hashes of (seed, pixel,
/// dimension) ("padding", Kollig and Keller 2002; scrambling by Burley 2020). With spp = 2^m the
/// points of a pixel form a (0,m,2)-net in each 2D projection: one point in every elementary
/// interval of area 1/spp. The random order is a nested uniform scramble of the index when spp is
/// a power of two (Burley 2020, section 4: a few integer operations) and Kensler's permutation
/// otherwise; the per-dimension seeds come from one 64-bit mix of a per-pixel hash.
class SobolSampler final : public Sampler {
 public:
  SobolSampler(int spp, uint64_t seed);
  int samples_per_pixel() const override { return spp_; }
  void start_pixel_sample(int px, int py, int index) override;
  float get_1d() override;
  Vec2 get_2d() override;
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<SobolSampler>(*this); }

 private:
  /// 64 fresh random bits for the next dimension.
  uint64_t next_hash();
  /// The shuffled index of this sample among the pixel's spp, for a dimension's seed.
  uint32_t shuffled(uint32_t seed) const;

  int spp_;
  int log2_spp_ = -1;  ///< m when spp = 2^m, else -1
  uint64_t seed_;
  uint64_t pixel_hash_ = 0;
  uint32_t index_ = 0;
  uint32_t dim_ = 0;
};

}  // namespace penumbra
