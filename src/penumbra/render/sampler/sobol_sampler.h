#pragma once
/// A low-discrepancy sampler: the Owen-scrambled (0,2)-sequence, padded across dimensions.
#include <cstdint>

#include "penumbra/render/sampler/sampler.h"

namespace penumbra {

/// Each pair of dimensions takes the first spp points of the (0,2)-sequence (the first two Sobol'
/// dimensions) in a random order and Owen-scrambled, both chosen by hashes of (seed, pixel,
/// dimension) ("padding", Kollig and Keller 2002; scrambling by Burley 2020). With spp = 2^m the
/// points of a pixel form a (0,m,2)-net in each 2D projection: one point in every elementary
/// interval of area 1/spp. The random order is a nested uniform scramble of the index when spp is
/// a power of two (Burley 2020, section 4: a few integer operations) and Kensler's permutation
/// otherwise; the per-dimension seeds are 32-bit mixes of the halves of a per-pixel hash.
///
/// With the pixel sample's hash P = hash_combine(seed, (py << 32) | px), P_lo and P_hi its low and
/// high 32 bits and G = 0x9e3779b9, dimension d (counted from 1 in the order of the calls;
/// get_2d takes two) has the seeds lo_d = mix32(P_lo + d G) and hi_d = mix32(P_hi + d G) (32-bit
/// arithmetic): get_1d at d returns the scrambled first Sobol' dimension of the index shuffled
/// by lo_d, scrambled by hi_d; get_2d at d pairs it with the second Sobol' dimension of the same
/// index, scrambled by lo_(d+1). The values are computed kBatch dimensions
/// at a time, in loops the compiler vectorises, and handed out by inline, non-virtual calls when
/// the caller knows the type (the path integrator does): a value costs a few instructions instead
/// of a chain of dependent multiplications and bit reversals per call.
class SobolSampler final : public Sampler {
 public:
  SobolSampler(int spp, uint64_t seed);
  int samples_per_pixel() const override { return spp_; }
  void start_pixel_sample(int px, int py, int index) override;
  float get_1d() override {
    const uint32_t k = slot();
    ++dim_;
    return x_[k];
  }
  Vec2 get_2d() override {
    const uint32_t k = slot();
    dim_ += 2;
    return {x_[k], y_[k]};
  }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<SobolSampler>(*this); }

 private:
  /// Dimensions computed at once: most paths need fewer than two batches. (Batches of 8, AVX2's
  /// width, would waste fewer values, as a Cornell box path takes 5 + 6 per vertex dimensions,
  /// but measured 2 % slower in paired renders.)
  static constexpr uint32_t kBatch = 16;

  /// The batch slot of the next dimension, computing the next batch when it is not there yet.
  uint32_t slot() {
    const uint32_t k = dim_ - base_;  // wraps to a large value before the first batch
    if (k < kBatch) [[likely]]
      return k;
    fill_batch();
    return 0;
  }
  /// Computes x_ and y_ for dimensions dim_ .. dim_ + kBatch - 1 and makes dim_ the base.
  void fill_batch();
  /// The shuffled index of this sample among the pixel's spp, for a dimension's seed.
  uint32_t shuffled(uint32_t seed) const;

  int spp_;
  int log2_spp_ = -1;  ///< m when spp = 2^m, else -1
  uint64_t seed_;
  uint64_t pixel_hash_ = 0;
  uint32_t index_ = 0;
  uint32_t reversed_index_ = 0;  ///< reverse_bits(index_ << (32 - m)) when spp = 2^m, m > 0
  uint32_t dim_ = 1;             ///< the next dimension
  uint32_t base_ = 0;            ///< the dimension of slot 0
  float x_[kBatch] = {};         ///< per slot: the first Sobol' dimension, scrambled
  float y_[kBatch] = {};         ///< per slot: the second, for get_2d
};

}  // namespace penumbra
