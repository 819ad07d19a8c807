#pragma once
/// A piecewise-constant 2D density on [0, 1)^2: a marginal density over rows and a conditional
/// density per row (pbrt-v4's PiecewiseConstant2D; Pharr, Jakob, Humphreys 2023, "Physically
/// Based Rendering", 4th ed., section A.5.2).
#include <span>
#include <vector>

#include "penumbra/core/vec.h"
#include "penumbra/render/sampling/distribution_1d.h"

namespace penumbra {

/// A continuous sample of a Distribution2D.
struct Sample2D {
  Vec2 p;         ///< the point, in [0, 1)^2 (x along a row, y across rows)
  float pdf = 0;  ///< its density on [0, 1)^2
  int x = 0;      ///< its column (cell index along x)
  int y = 0;      ///< its row
};

/// The density proportional to a non-negative function of nx x ny equal cells on [0, 1)^2.
/// Immutable and thread-safe; sampling is two binary searches (O(log nx + log ny)), deterministic.
/// Rows whose function is zero are never drawn; a function that is zero everywhere gives the
/// uniform density 1. As for Distribution1D, `pdf` is exactly the density `sample` draws from.
class Distribution2D {
 public:
  /// The uniform density on one cell.
  Distribution2D() : Distribution2D(std::span<const float>(), 0, 0) {}
  /// The density proportional to f, row-major: f[y * nx + x] is the cell [x/nx, (x+1)/nx) x
  /// [y/ny, (y+1)/ny). f must hold nx * ny values (nx, ny > 0), or be empty for one uniform cell.
  Distribution2D(std::span<const float> f, int nx, int ny);

  /// Cells along x.
  int nx() const { return conditional_[0].size(); }
  /// Cells along y (rows).
  int ny() const { return marginal_.size(); }
  /// Integral of f over [0, 1)^2; 0 when f is zero everywhere.
  double integral() const { return marginal_.integral(); }
  /// Samples a point from u in [0, 1)^2: the row with u.y, then the column in it with u.x.
  Sample2D sample(Vec2 u) const;
  /// The density at p in [0, 1)^2 (clamped to it).
  float pdf(Vec2 p) const { return cell_pdf(conditional_[0].cell_of(p.x), marginal_.cell_of(p.y)); }
  /// The density on cell (x, y).
  float cell_pdf(int x, int y) const { return marginal_.cell_pdf(y) * conditional_[y].cell_pdf(x); }

 private:
  std::vector<Distribution1D> conditional_;  ///< one per row: the density along x in that row
  Distribution1D marginal_;                  ///< over rows, proportional to their integrals
};

}  // namespace penumbra
