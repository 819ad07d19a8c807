#pragma once
/// Stratified sampling: `jittered` (a random point in each stratum) and `regular` (each stratum's
/// centre, the lecture's uniform supersampling grid).
#include "penumbra/core/rng.h"
#include "penumbra/render/sampler/sampler.h"

namespace penumbra {

/// Samples per pixel split into nx x ny strata (nx ny = spp, nx and ny as close as possible). The
/// pixel position of sample i lies in stratum i; every other dimension is stratified as well, with
/// the strata visited in a pseudo-random order chosen per (pixel, dimension) so dimensions do not
/// correlate (Kensler's permutations). `jittered` places each point uniformly inside its stratum;
/// `regular` at the stratum's centre, which aliases on high frequencies as the lecture warns.
class StratifiedSampler final : public Sampler {
 public:
  StratifiedSampler(int spp, uint64_t seed, bool jitter);
  int samples_per_pixel() const override { return spp_; }
  void start_pixel_sample(int px, int py, int index) override;
  float get_1d() override;
  Vec2 get_2d() override;
  Vec2 get_pixel_2d() override;
  std::unique_ptr<Sampler> clone() const override {
    return std::make_unique<StratifiedSampler>(*this);
  }
  /// Strata along x and y of the pixel.
  int strata_x() const { return nx_; }
  int strata_y() const { return ny_; }

 private:
  /// Offset within a stratum: uniform when jittering, else the centre.
  float offset();
  uint32_t dimension_seed();

  int spp_, nx_, ny_;
  uint64_t seed_;
  bool jitter_;
  uint64_t pixel_ = 0;
  int index_ = 0;
  uint32_t dim_ = 0;
  Pcg32 rng_;
};

}  // namespace penumbra
