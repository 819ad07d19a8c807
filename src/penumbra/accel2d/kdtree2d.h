#pragma once
/// A 2D kd-tree over segments (Bentley 1975, "Multidimensional binary search trees used for
/// associative searching"): a cell holding more than `leaf` segments is split across its longer
/// side at the median of the segments' midpoints (the middle when the median is on the border); a
/// segment goes to every side it reaches. Walked front to back like the BSPs (line_tree.h).
#include <string>
#include <vector>

#include "penumbra/accel2d/accel2d.h"
#include "penumbra/accel2d/line_tree.h"
#include "penumbra/core/params.h"

namespace penumbra::lab2d {

/// The 2D kd-tree. Parameters: leaf=2 (most segments in a leaf), depth=24.
class KdTree2D final : public Accel2D {
 public:
  /// Reads `leaf` and `depth` from p (rejecting others).
  explicit KdTree2D(const ParamList& p);

  std::string name() const override;
  void build(const Scene2D& scene) override;
  Hit2 shoot(const Ray2& ray, TraceLog* trace = nullptr) const override;
  Stats2D stats() const override;
  Drawing2D draw(const Box2d& frame) const override;

 private:
  size_t leaf_ = 2;
  size_t max_depth_ = 24;
  double eps_ = 0;
  std::vector<Segment2> segs_;
  LineTree tree_;
  double build_ms_ = 0;
};

}  // namespace penumbra::lab2d
