#pragma once
/// A quadtree over segments (Finkel and Bentley 1974, "Quad trees: a data structure for retrieval
/// on composite keys"; for segments, the PMR/MX variants surveyed by Samet 1990, "The Design and
/// Analysis of Spatial Data Structures"): the bounding square is divided into four equal squares,
/// and every square holding more than `leaf` segments is divided again, up to `depth` levels. A
/// segment is referenced by every square it meets. Rays visit children in order of entry.
#include <string>
#include <vector>

#include "penumbra/accel2d/accel2d.h"
#include "penumbra/core/params.h"

namespace penumbra::lab2d {

/// The quadtree. Parameters: leaf=2 (most segments in a leaf), depth=12.
class Quadtree2D final : public Accel2D {
 public:
  /// Reads `leaf` and `depth` from p (rejecting others).
  explicit Quadtree2D(const ParamList& p);

  std::string name() const override;
  void build(const Scene2D& scene) override;
  Hit2 shoot(const Ray2& ray, TraceLog* trace = nullptr) const override;
  Stats2D stats() const override;
  Drawing2D draw(const Box2d& frame) const override;

 private:
  /// A square; children are four consecutive nodes (x-major: lo-lo, hi-lo, lo-hi, hi-hi).
  struct Node {
    Box2d box;
    uint32_t first_child = 0;  ///< 0: a leaf (the root is never a child)
    uint32_t first = 0, count = 0;
    uint32_t number = 0;  ///< internal nodes: k of the label qk (preorder from 1)
  };
  /// "qk" for an internal node; a leaf's segments ("s3,s7") or "empty".
  std::string label(uint32_t node) const;

  size_t leaf_ = 2;
  size_t max_depth_ = 12;
  double eps_ = 0;
  std::vector<Segment2> segs_;
  std::vector<Node> nodes_;
  std::vector<uint32_t> refs_;
  size_t depth_ = 0;
  double build_ms_ = 0;
};

}  // namespace penumbra::lab2d
