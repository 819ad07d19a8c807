#pragma once
/// Samplers produce the random numbers of one pixel sample. Their values depend only on (pixel,
/// sample index, seed), never on the thread or the order of work, so renders are deterministic.
#include <memory>

#include "penumbra/core/vec.h"

namespace penumbra {

/// Source of sample values for one pixel sample at a time; one instance per thread (`clone`).
class Sampler {
 public:
  virtual ~Sampler() = default;
  /// Samples per pixel this sampler was made for.
  virtual int samples_per_pixel() const = 0;
  /// Positions the sampler at sample `index` of pixel (px, py).
  virtual void start_pixel_sample(int px, int py, int index) = 0;
  /// Next value in [0, 1).
  virtual float get_1d() = 0;
  /// Next pair in [0, 1)^2.
  virtual Vec2 get_2d() = 0;
  /// The position within the pixel, in [0, 1)^2 (stratified samplers place it in a stratum).
  virtual Vec2 get_pixel_2d() { return get_2d(); }
  /// An independent copy for another thread.
  virtual std::unique_ptr<Sampler> clone() const = 0;
};

}  // namespace penumbra
