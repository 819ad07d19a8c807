#pragma once
/// The object variant of the 2D BSP: disjoint convex objects (polygons, or segments) stored only at
/// leaves, splitting lines chosen freely; an object a line cuts goes to both sides, so it may sit
/// in several leaves (like O5 in the lecture's example). Rule for the lines (docs/lab2d.md): among
/// the lines through the objects' edges, the one cutting the fewest objects of the cell, ties to
/// the better balance, among those leaving at least one object wholly on each side; by the
/// separating axis theorem two disjoint convex objects always have such an edge line.
#include <string>
#include <vector>

#include "penumbra/accel2d/accel2d.h"
#include "penumbra/accel2d/line_tree.h"
#include "penumbra/core/params.h"

namespace penumbra::lab2d {

/// The object BSP. Parameters: candidates=64 (edge lines scored per node; all when fewer).
class ObjectBsp final : public Accel2D {
 public:
  /// Reads `candidates` from p (rejecting others).
  explicit ObjectBsp(const ParamList& p);

  std::string name() const override;
  void build(const Scene2D& scene) override;
  Hit2 shoot(const Ray2& ray, TraceLog* trace = nullptr) const override;
  Stats2D stats() const override;
  Drawing2D draw(const Box2d& frame) const override;

  /// The tree: nodes (root first) and the object ids the leaves' ranges index.
  const LineTree& tree() const { return tree_; }

 private:
  size_t candidates_ = 64;
  double eps_ = 0;
  std::vector<std::vector<Vec2d>> objects_;
  LineTree tree_;
  double build_ms_ = 0;
};

}  // namespace penumbra::lab2d
