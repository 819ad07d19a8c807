#pragma once
/// A piecewise-constant 1D density on [0, 1), sampled by inverting its CDF (pbrt-v4's
/// PiecewiseConstant1D; Pharr, Jakob, Humphreys 2023, "Physically Based Rendering", 4th ed.,
/// section A.4.2).
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

/// A continuous sample of a Distribution1D.
struct Sample1D {
  float x = 0;    ///< the point, in [0, 1)
  float pdf = 0;  ///< its density on [0, 1)
  int cell = 0;   ///< the cell it lies in (floor(x * size()), computed exactly)
};

/// The density proportional to a non-negative step function of n equal cells on [0, 1). Immutable
/// and thread-safe; sampling is a binary search on the CDF (O(log n)) and fully deterministic.
///
/// Densities are the CDF's cell widths times n, so `pdf` is exactly the density `sample` draws
/// from (a cell whose share rounds to zero in float is never drawn and has density 0). A function
/// that is zero everywhere (or has no positive finite cell) gives the uniform density 1.
class Distribution1D {
 public:
  /// The uniform density on one cell.
  Distribution1D() : Distribution1D(std::span<const float>()) {}
  /// The density proportional to f (cell i is [i/n, (i+1)/n)); negative and NaN values count as
  /// zero. An empty f is one cell of uniform density.
  explicit Distribution1D(std::span<const float> f);

  /// Number of cells.
  int size() const { return static_cast<int>(cdf_.size()) - 1; }
  /// Integral of f over [0, 1) (the mean of its cells); 0 when f is zero everywhere.
  double integral() const { return integral_; }
  /// Samples x with density pdf(x) from u in [0, 1) (clamped to it).
  Sample1D sample(float u) const;
  /// The density at x in [0, 1) (clamped to it).
  float pdf(float x) const { return cell_pdf(cell_of(x)); }
  /// The density on cell i.
  float cell_pdf(int i) const { return (cdf_[i + 1] - cdf_[i]) * static_cast<float>(size()); }
  /// The probability of cell i: cell_pdf(i) / size().
  float cell_probability(int i) const { return cdf_[i + 1] - cdf_[i]; }
  /// The cell that contains x (clamped to [0, size() - 1]).
  int cell_of(float x) const;

 private:
  std::vector<float> cdf_;  ///< size() + 1 values, cdf_[0] = 0, cdf_[size()] = 1
  double integral_ = 0;
};

}  // namespace penumbra
