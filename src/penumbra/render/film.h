#pragma once
/// The film: per-pixel weighted sums of radiance samples, resolved into an image, with the
/// statistics of a per-pixel variance estimate.
#include <cstdint>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/image/image.h"

namespace penumbra {

/// Accumulates weighted radiance samples per pixel in double precision. Each pixel is written by
/// one thread at a time (the renderer hands out whole tiles), so no synchronisation is needed.
/// Reconstruction filters come by weighting samples (filter importance sampling), never by
/// splatting into neighbours, which keeps pixels independent and results deterministic: a
/// pixel's sums depend only on its samples in index order, whatever the pass schedule.
///
/// A pixel's value is the weighted mean m = sum w L / sum w. Its variance is estimated from the
/// same samples, treating them as independent: Var[m] ~ sum w^2 (L - m)^2 / (sum w)^2, computed
/// per channel from the running sums of w^2, w^2 L and w^2 L^2.
class Film {
 public:
  /// Throws Error (core/memory_limit.h) when the film and the images resolved from it would
  /// exceed the memory limit.
  Film(int width, int height);
  /// Bytes a film of this size takes, with its resolved and variance images and an encoded copy.
  static double memory_bytes(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  /// Adds sample radiance `l` with `weight` to pixel (x, y).
  void add_sample(int x, int y, Rgb l, float weight = 1.0f);
  /// Replaces pixel (x, y) by the estimate `value`, counted as `samples` samples (for
  /// integrators whose pixel value is not a mean of samples, such as SPPM's); its variance reads
  /// as zero.
  void set_pixel(int x, int y, Rgb value, uint32_t samples);
  /// The image of weighted means; pixels without samples are black.
  RgbImage resolve() const;
  /// Per pixel and channel, the estimated variance of the pixel's mean (zero without samples).
  RgbImage variance() const;
  /// The mean over pixels of the relative standard error of the pixel's luminance,
  /// sqrt(Var[Y]) / max(Y, floor) with floor = 1e-3 times the image's mean luminance (so black
  /// and nearly black pixels do not dominate); zero for an empty film.
  double mean_relative_error() const;
  /// Samples added to pixel (x, y).
  uint32_t samples(int x, int y) const { return pixel(x, y).count; }

 private:
  struct Pixel {
    double sum[3] = {0, 0, 0};       ///< sum w L
    double weight = 0;               ///< sum w
    double sum_w2 = 0;               ///< sum w^2
    double sum_w2l[3] = {0, 0, 0};   ///< sum w^2 L
    double sum_w2l2[3] = {0, 0, 0};  ///< sum w^2 L^2
    uint32_t count = 0;
  };
  const Pixel& pixel(int x, int y) const { return pixels_[size_t(y) * size_t(width_) + size_t(x)]; }
  /// The variance of the mean of channel c of p.
  static double channel_variance(const Pixel& p, int c);

  int width_, height_;
  std::vector<Pixel> pixels_;
};

// Inline: every camera sample of every integrator adds itself here.
inline void Film::add_sample(int x, int y, Rgb l, float weight) {
  Pixel& p = pixels_[size_t(y) * size_t(width_) + size_t(x)];
  const double w = weight, w2 = w * w;
  for (int c = 0; c < 3; ++c) {
    const double v = l[c];
    p.sum[c] += v * w;
    p.sum_w2l[c] += w2 * v;
    p.sum_w2l2[c] += w2 * v * v;
  }
  p.weight += w;
  p.sum_w2 += w2;
  ++p.count;
}

}  // namespace penumbra
