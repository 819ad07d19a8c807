#include "penumbra/accel2d/kdtree2d.h"

#include <algorithm>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/timer.h"

namespace penumbra::lab2d {

KdTree2D::KdTree2D(const ParamList& p)
    : leaf_(size_t(p.get_int("leaf", 2, 1, 1 << 20))),
      max_depth_(size_t(p.get_int("depth", 24, 0, 60))) {
  p.check_all_used();
}

std::string KdTree2D::name() const {
  return fmt::format("kdtree:leaf={},depth={}", leaf_, max_depth_);
}

void KdTree2D::build(const Scene2D& scene) {
  const Timer timer;
  if (!scene.all_segments()) throw Error(scene.source + ": the kd-tree takes segments only");
  segs_.clear();
  for (const Shape2& s : scene.shapes) segs_.push_back(s.segment());
  eps_ = scene.eps();
  tree_ = LineTree{};
  struct Job {
    Box2d box;
    std::vector<uint32_t> ids;
    uint32_t parent;
    int side;
    uint32_t depth;
  };
  std::vector<Job> jobs(1);
  jobs[0].box = scene.bounds();
  jobs[0].parent = LineNode::kNone;
  for (uint32_t k = 0; k < segs_.size(); ++k) jobs[0].ids.push_back(k);
  std::vector<double> mids;
  while (!jobs.empty()) {
    Job job = std::move(jobs.back());
    jobs.pop_back();
    tree_.depth = std::max<size_t>(tree_.depth, job.depth);
    LineNode node;
    uint32_t index = LineNode::kNone;
    if (job.ids.size() > leaf_ && job.depth < max_depth_) {
      // The longer axis, at the median midpoint (the middle when that is on the border).
      const Vec2d ext = job.box.extent();
      const int axis = ext.x >= ext.y ? 0 : 1;
      const double lo = axis == 0 ? job.box.lo.x : job.box.lo.y;
      const double hi = axis == 0 ? job.box.hi.x : job.box.hi.y;
      mids.clear();
      for (uint32_t id : job.ids) {
        const Vec2d m = (segs_[id].a + segs_[id].b) * 0.5;
        mids.push_back(axis == 0 ? m.x : m.y);
      }
      std::nth_element(mids.begin(), mids.begin() + mids.size() / 2, mids.end());
      double split = mids[mids.size() / 2];
      if (!(split > lo && split < hi)) split = 0.5 * (lo + hi);
      Job sides[2];
      sides[0].box = sides[1].box = job.box;
      (axis == 0 ? sides[0].box.lo.x : sides[0].box.lo.y) = split;  // ℓ⁺: coordinate > split
      (axis == 0 ? sides[1].box.hi.x : sides[1].box.hi.y) = split;
      for (int side = 0; side < 2; ++side)
        for (uint32_t id : job.ids)
          if (segment_overlaps_box(segs_[id], sides[side].box, eps_)) sides[side].ids.push_back(id);
      // Split only when it separates something.
      if (sides[0].ids.size() < job.ids.size() || sides[1].ids.size() < job.ids.size()) {
        node.line = axis == 0 ? Line2{1, 0, split} : Line2{0, 1, split};
        index = tree_.add(node, true);
        for (int side = 1; side >= 0; --side) {
          sides[side].parent = index;
          sides[side].side = side;
          sides[side].depth = job.depth + 1;
          jobs.push_back(std::move(sides[side]));
        }
      }
    }
    if (index == LineNode::kNone) {
      node.first = uint32_t(tree_.refs.size());
      node.count = uint32_t(job.ids.size());
      tree_.refs.insert(tree_.refs.end(), job.ids.begin(), job.ids.end());
      index = tree_.add(node, false);
    }
    if (job.parent != LineNode::kNone) tree_.nodes[job.parent].child[job.side] = index;
  }
  build_ms_ = timer.elapsed_ms();
}

Hit2 KdTree2D::shoot(const Ray2& ray, TraceLog* trace) const {
  return shoot_line_tree(
      tree_, ray, eps_, [&](uint32_t id) { return intersect(ray, segs_[id]); }, trace);
}

Stats2D KdTree2D::stats() const {
  Stats2D s = line_tree_stats(tree_, build_ms_);
  s.extra = {{"segments", double(segs_.size())}};
  return s;
}

Drawing2D KdTree2D::draw(const Box2d& frame) const {
  return draw_line_tree(tree_, frame);
}

}  // namespace penumbra::lab2d
