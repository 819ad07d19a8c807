#pragma once
/// A uniform 2D grid over segments, walked cell by cell with the 2D DDA of Amanatides and Woo
/// (1987, "A fast voxel traversal algorithm for ray tracing"). About lambda · n square-ish cells
/// over the bounding box; a segment is referenced by every cell it meets; the walk stops at the
/// first cell whose exit lies beyond the closest hit.
#include <string>
#include <vector>

#include "penumbra/accel2d/accel2d.h"
#include "penumbra/core/params.h"

namespace penumbra::lab2d {

/// The grid. Parameters: lambda=1 (cells per segment), max=4096 (cells per axis at most).
class Grid2D final : public Accel2D {
 public:
  /// Reads `lambda` and `max` from p (rejecting others).
  explicit Grid2D(const ParamList& p);

  std::string name() const override;
  void build(const Scene2D& scene) override;
  Hit2 shoot(const Ray2& ray, TraceLog* trace = nullptr) const override;
  Stats2D stats() const override;
  Drawing2D draw(const Box2d& frame) const override;

 private:
  /// The box of cell (i, j).
  Box2d cell_box(int i, int j) const;

  double lambda_ = 1;
  int max_res_ = 4096;
  double eps_ = 0;
  std::vector<Segment2> segs_;
  Box2d box_;
  int nx_ = 1, ny_ = 1;
  Vec2d cell_{1, 1};
  std::vector<uint32_t> offsets_;  ///< cell c's references: refs_[offsets_[c], offsets_[c + 1])
  std::vector<uint32_t> refs_;
  double build_ms_ = 0;
};

}  // namespace penumbra::lab2d
