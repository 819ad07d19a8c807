#pragma once
/// The film: per-pixel weighted sums of radiance samples, resolved into an image.
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/image/image.h"

namespace penumbra {

/// Accumulates weighted radiance samples per pixel in double precision. Each pixel is written by
/// one thread at a time (the renderer hands out whole tiles), so no synchronisation is needed.
/// Reconstruction filters come by weighting samples (filter importance sampling), never by
/// splatting into neighbours, which keeps pixels independent and results deterministic.
class Film {
 public:
  Film(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  /// Adds sample radiance `l` with `weight` to pixel (x, y).
  void add_sample(int x, int y, Rgb l, float weight = 1.0f);
  /// The image of weighted means; pixels without samples are black.
  RgbImage resolve() const;

 private:
  struct Pixel {
    double r = 0, g = 0, b = 0, weight = 0;
  };
  int width_, height_;
  std::vector<Pixel> pixels_;
};

}  // namespace penumbra
