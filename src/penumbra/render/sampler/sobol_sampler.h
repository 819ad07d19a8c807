#pragma once
/// A low-discrepancy sampler: the Owen-scrambled (0,2)-sequence, padded across dimensions.
#include <cstdint>

#include "penumbra/core/lanes.h"
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

  /// The first pair of every pixel sample.
  static constexpr uint32_t kFirstPair = 1;
  /// For a caller that computes this pixel sample's next values itself, with SobolLanes: the
  /// next pair get_1d or get_2d would open, and whether get_1d would return a pending value.
  uint32_t next_pair() const { return dim_; }
  bool has_pending() const { return has_pending_; }
  float pending() const { return pending_; }
  /// Continues after values the caller computed: `pair` is the next pair, and get_1d's pending
  /// value is `pending_value` when `pending` (the state the draws themselves would have left).
  void resume(uint32_t pair, bool pending, float pending_value) {
    dim_ = pair;
    has_pending_ = pending;
    pending_ = pending_value;
  }

 private:
  friend class SobolLanes;
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
  uint32_t dim_ = kFirstPair;    ///< the next pair
  uint32_t base_ = 0;            ///< the pair of slot 0
  float x_[kBatch] = {};         ///< per slot: the first Sobol' dimension, scrambled
  float y_[kBatch] = {};         ///< per slot: the second
  float pending_ = 0;            ///< the second value of the pair the last get_1d opened
  bool has_pending_ = false;     ///< pending_ is not used yet
};

/// The pairs of eight SobolSampler pixel samples at once, one sample per lane (its keys taken by
/// set): each call gives, per vector lane, the values that get_2d returns for some pair of some
/// lane's sample, eight in one vector batch. A sampler's own batch computes 16 consecutive pairs
/// of one sample, of which a short path draws about half; a caller that shades eight paths at
/// once (PathLanes) computes just the pairs its paths draw, and takes them as vectors. All
/// lanes share the samples per pixel.
class SobolLanes {
 public:
  static constexpr int kWidth = 8;
  explicit SobolLanes(const SobolSampler& s) : log2_spp_(s.log2_spp_), spp_(uint32_t(s.spp_)) {}
  /// Lane k takes the keys of the current pixel sample of s (same samples per pixel).
  void set(int k, const SobolSampler& s) {
    lo_[k] = uint32_t(s.pixel_hash_), hi_[k] = uint32_t(s.pixel_hash_ >> 32);
    reversed_[k] = s.reversed_index_, index_[k] = s.index_;
  }
  /// Lane k of x and y: pair pair[k] of the sample in lane lane[k] (taken modulo 8), so that a
  /// few lanes' pairs fill one vector. Lanes never set give some sample's values.
  void compute(lanes::U8 lane, lanes::U8 pair, lanes::F8& x, lanes::F8& y) const;
  /// Lane k of x[j] and y[j], j < 3: pair first[k] + j of lane k's own sample, the three in one
  /// go (their dependency chains overlap).
  void compute3(lanes::U8 first, lanes::F8 (&x)[3], lanes::F8 (&y)[3]) const;

 private:
  static lanes::U8 load(const uint32_t* p) {
    lanes::U8 v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
  }
  alignas(32) uint32_t lo_[kWidth] = {}, hi_[kWidth] = {}, reversed_[kWidth] = {};
  alignas(32) uint32_t index_[kWidth] = {};
  int log2_spp_;
  uint32_t spp_;
};

}  // namespace penumbra
