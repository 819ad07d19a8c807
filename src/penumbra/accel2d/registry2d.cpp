#include "penumbra/accel2d/registry2d.h"

#include <functional>

#include "penumbra/accel2d/grid2d.h"
#include "penumbra/accel2d/kdtree2d.h"
#include "penumbra/accel2d/object_bsp.h"
#include "penumbra/accel2d/quadtree2d.h"
#include "penumbra/accel2d/segment_bsp.h"
#include "penumbra/core/params.h"
#include "penumbra/core/registry.h"

namespace penumbra::lab2d {

namespace {

/// What the registry keeps per structure: its input requirements and its factory.
struct Maker {
  bool segments_only;  ///< true when it takes segments only
  bool disjoint;       ///< true when its theory needs disjoint input
  std::function<std::unique_ptr<Accel2D>(const ParamList&)> make;
};

template <class T>
std::unique_ptr<Accel2D> create(const ParamList& p) {
  return std::make_unique<T>(p);
}

std::unique_ptr<Accel2D> create_brute(const ParamList& p) {
  p.check_all_used();
  return std::make_unique<Brute2D>();
}

/// Every structure, written out explicitly: a new one is one line here.
const Registry<Maker>& registry() {
  static const Registry<Maker> all = {
      {"bsp",
       "2D BSP of segments by auto-partition (order=random|first|fewest-cuts, seed=1)",
       {true, true, create<SegmentBsp>}},
      {"objects",
       "BSP of disjoint convex objects at the leaves, edge lines (candidates=64)",
       {false, true, create<ObjectBsp>}},
      {"quadtree", "quadtree over segments (leaf=2, depth=12)", {true, false, create<Quadtree2D>}},
      {"kdtree",
       "2D kd-tree over segments, median splits (leaf=2, depth=24)",
       {true, false, create<KdTree2D>}},
      {"grid",
       "uniform 2D grid over segments, DDA walk (lambda=1, max=4096)",
       {true, false, create<Grid2D>}},
      {"brute",
       "brute force: every shape for every ray (the reference)",
       {false, false, create_brute}},
  };
  return all;
}

}  // namespace

const std::vector<Accel2DInfo>& accel2d_list() {
  static const std::vector<Accel2DInfo> list = [] {
    std::vector<Accel2DInfo> l;
    for (const auto& e : registry().entries())
      l.push_back({e.name, e.description, e.factory.segments_only, e.factory.disjoint});
    return l;
  }();
  return list;
}

std::unique_ptr<Accel2D> make_accel2d(std::string_view spec) {
  const ParamList params = ParamList::parse(spec);
  return registry().get(params.name(), "2D structure").make(params);
}

Hit2 Brute2D::shoot(const Ray2& ray, TraceLog* trace) const {
  if (trace) trace->enter(0, "all");
  Hit2 h;
  h.t = shoot_brute(scene_, ray, h.id);
  return h;
}

Stats2D Brute2D::stats() const {
  Stats2D s;
  s.nodes = s.leaves = 1;
  s.fragments = scene_.shapes.size();
  return s;
}

Drawing2D Brute2D::draw(const Box2d& frame) const {
  Drawing2D d;
  d.frame = frame;
  return d;
}

}  // namespace penumbra::lab2d
