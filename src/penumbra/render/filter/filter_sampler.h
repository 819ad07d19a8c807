#pragma once
/// Draws pixel sample offsets distributed as |f| of a separable filter, with their weights.
#include <vector>

#include "penumbra/core/vec.h"
#include "penumbra/render/filter/filter.h"

namespace penumbra {

/// A filter offset and the weight f(offset) / pdf(offset) that makes the weighted mean of the
/// samples converge to the filtered image (filter importance sampling; pbrt-v4 section 8.8).
struct FilterSample {
  Vec2 offset;  ///< from the pixel centre, in pixels
  float weight;
};

/// Tabulates f1 at `resolution` + 1 nodes on [-radius, radius]; the filter used is the
/// piecewise-linear interpolant of those values (exact for box and tent), whose absolute value is
/// sampled by inverting its piecewise-quadratic CDF in each axis.
class FilterSampler {
 public:
  explicit FilterSampler(const Filter& filter, int resolution = 256);
  /// The sample for the uniform pair u in [0,1)^2.
  FilterSample sample(Vec2 u) const;
  /// Density of the 1D marginal at x (for tests).
  float pdf_1d(float x) const;

 private:
  float sample_1d(float u, float& pdf) const;
  float sign_at(float x) const;

  float radius_;
  std::vector<float> f_;    ///< f1 at the table's nodes (signed)
  std::vector<float> abs_;  ///< |f1| at the nodes
  std::vector<float> cdf_;  ///< integral of |f1| up to each node, normalised to 1
  float integral_ = 0;      ///< integral of |f1| over [-radius, radius]
  bool box_ = false;        ///< |f1| constant: sample uniformly, exactly
};

}  // namespace penumbra
