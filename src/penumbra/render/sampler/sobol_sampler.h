#pragma once
/// A low-discrepancy sampler: the Owen-scrambled (0,2)-sequence, padded across dimensions.
#include <cstdint>

#include "penumbra/render/sampler/sampler.h"

namespace penumbra {

/// Each pair of dimensions takes the first spp points of the (0,2)-sequence (the first two Sobol'
/// dimensions) in a random order and Owen-scrambled, both chosen by hashes of (seed, pixel,
/// pair) ("padding", Kollig and Keller 2002; scrambling by Burley 2020). With spp = 2^m the
/// points of a pixel form a (0,m,2)-net in each 2D projection: one point in every elementary
/// interval of area 1/spp. The random order is a nested uniform scramble of the index when spp is
/// a power of two (Burley 2020, section 4: a few integer operations) and Kensler's permutation
/// otherwise; the per-pair seeds are 32-bit mixes of the halves of a per-pixel hash.
///
/// With the pixel sample's hash P = hash_combine(seed, (py << 32) | px), P_lo and P_hi its low and
/// high 32 bits and G = 0x9e3779b9, pair s (counted from 1) has the seeds lo_s = mix32(P_lo +
/// s G), hi_s = mix32(P_hi + s G) and yk_s = mix32(P_hi + s G + 0x6a09e667) (32-bit arithmetic):
/// its point is the first and second Sobol' dimensions of the index shuffled by lo_s, scrambled
/// by hi_s and by yk_s. get_2d returns the next pair's point. get_1d returns the second
/// coordinate of the last pair that a get_1d opened and has not yet used, else opens the next pair
/// and returns its first coordinate: two 1D draws share one pair, in whatever order they come
/// among the 2D draws (a path vertex's light and BSDF pairs and its lobe and roulette numbers take
/// three pairs). Every value computed is used, and the two numbers of a shared pair are
/// stratified together. The values are computed kBatch pairs at a time, in loops the compiler
/// vectorises, and handed out by inline, non-virtual calls when the caller knows the type (the
/// path integrator does): a value costs a few instructions instead of a chain of dependent
/// multiplications and bit reversals per call.
class SobolSampler final : public Sampler {
 public:
  SobolSampler(int spp, uint64_t seed);
  int samples_per_pixel() const override { return spp_; }
  void start_pixel_sample(int px, int py, int index) override;
  float get_1d() override {
    if (has_pending_) {
      has_pending_ = false;
      return pending_;
    }
    const uint32_t k = slot();
    ++dim_;
    pending_ = y_[k];
    has_pending_ = true;
    return x_[k];
  }
  Vec2 get_2d() override {
    const uint32_t k = slot();
    ++dim_;
    return {x_[k], y_[k]};
  }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<SobolSampler>(*this); }

 private:
  /// Pairs computed at once: a Cornell box path takes 3 + 3 per vertex, so most paths need one
  /// batch. (Batches of 8, AVX2's width, were no faster in paired Cornell box renders: 0.898-0.915
  /// against 0.908-0.925 Msamples/s.)
  static constexpr uint32_t kBatch = 16;

  /// The batch slot of the next pair, computing the next batch when it is not there yet.
  uint32_t slot() {
    const uint32_t k = dim_ - base_;  // wraps to a large value before the first batch
    if (k < kBatch) [[likely]]
      return k;
    fill_batch();
    return 0;
  }
  /// Computes x_ and y_ for pairs dim_ .. dim_ + kBatch - 1 and makes dim_ the base.
  void fill_batch();
  /// The shuffled index of this sample among the pixel's spp, for a pair's seed.
  uint32_t shuffled(uint32_t seed) const;

  int spp_;
  int log2_spp_ = -1;  ///< m when spp = 2^m, else -1
  uint64_t seed_;
  uint64_t pixel_hash_ = 0;
  uint32_t index_ = 0;
  uint32_t reversed_index_ = 0;  ///< reverse_bits(index_ << (32 - m)) when spp = 2^m, m > 0
  uint32_t dim_ = 1;             ///< the next pair
  uint32_t base_ = 0;            ///< the pair of slot 0
  float x_[kBatch] = {};         ///< per slot: the first Sobol' dimension, scrambled
  float y_[kBatch] = {};         ///< per slot: the second
  float pending_ = 0;            ///< the second value of the pair the last get_1d opened
  bool has_pending_ = false;     ///< pending_ is not used yet
};

}  // namespace penumbra
