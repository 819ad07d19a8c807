#include "penumbra/accel2d/quadtree2d.h"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/timer.h"

namespace penumbra::lab2d {

Quadtree2D::Quadtree2D(const ParamList& p)
    : leaf_(size_t(p.get_int("leaf", 2, 1, 1 << 20))),
      max_depth_(size_t(p.get_int("depth", 12, 0, 30))) {
  p.check_all_used();
}

std::string Quadtree2D::name() const {
  return fmt::format("quadtree:leaf={},depth={}", leaf_, max_depth_);
}

void Quadtree2D::build(const Scene2D& scene) {
  const Timer timer;
  if (!scene.all_segments()) throw Error(scene.source + ": the quadtree takes segments only");
  segs_.clear();
  for (const Shape2& s : scene.shapes) segs_.push_back(s.segment());
  eps_ = scene.eps();
  nodes_.clear();
  refs_.clear();
  depth_ = 0;
  // The bounding square, centred on the bounding box.
  const Box2d b = scene.bounds();
  const Vec2d c = (b.lo + b.hi) * 0.5;
  const double half = std::max({b.extent().x, b.extent().y, eps_}) * 0.5;
  Node root;
  root.box = {{c.x - half, c.y - half}, {c.x + half, c.y + half}};
  nodes_.push_back(root);
  struct Job {
    uint32_t node, depth;
    std::vector<uint32_t> ids;
  };
  std::vector<Job> jobs(1);
  jobs[0] = {0, 0, {}};
  for (uint32_t k = 0; k < segs_.size(); ++k) jobs[0].ids.push_back(k);
  uint32_t number = 0;
  while (!jobs.empty()) {
    Job job = std::move(jobs.back());
    jobs.pop_back();
    depth_ = std::max<size_t>(depth_, job.depth);
    if (job.ids.size() <= leaf_ || job.depth >= max_depth_) {
      nodes_[job.node].first = uint32_t(refs_.size());
      nodes_[job.node].count = uint32_t(job.ids.size());
      refs_.insert(refs_.end(), job.ids.begin(), job.ids.end());
      continue;
    }
    // Four equal squares; each takes the segments that meet it. Pushed in reverse so that the
    // first child is built next (preorder numbering of the labels).
    const Box2d box = nodes_[job.node].box;
    const Vec2d mid = (box.lo + box.hi) * 0.5;
    const uint32_t first = uint32_t(nodes_.size());
    nodes_[job.node].first_child = first;
    nodes_[job.node].number = ++number;
    for (int q = 0; q < 4; ++q) {
      Node child;
      child.box.lo = {q & 1 ? mid.x : box.lo.x, q & 2 ? mid.y : box.lo.y};
      child.box.hi = {q & 1 ? box.hi.x : mid.x, q & 2 ? box.hi.y : mid.y};
      nodes_.push_back(child);
    }
    for (int q = 3; q >= 0; --q) {
      Job child{first + q, job.depth + 1, {}};
      for (uint32_t id : job.ids)
        if (segment_overlaps_box(segs_[id], nodes_[first + q].box, eps_)) child.ids.push_back(id);
      jobs.push_back(std::move(child));
    }
  }
  build_ms_ = timer.elapsed_ms();
}

std::string Quadtree2D::label(uint32_t node) const {
  const Node& n = nodes_[node];
  if (n.first_child != 0) return fmt::format("q{}", n.number);
  if (n.count == 0) return "empty";
  std::string s;
  for (uint32_t k = n.first; k < n.first + n.count; ++k)
    fmt::format_to(std::back_inserter(s), "{}s{}", k == n.first ? "" : ",", refs_[k] + 1);
  return s;
}

Hit2 Quadtree2D::shoot(const Ray2& ray, TraceLog* trace) const {
  Hit2 best;
  struct Entry {
    uint32_t node, depth;
    double t0;
  };
  // Each level pushes at most four entries: the stack never exceeds 3 · depth + 1 <= 3 · 30 + 1.
  Entry stack[4 * 32];
  size_t sp = 0;
  // Boxes are grown by 2 eps so that a ray along a dividing line (or the border) visits both sides.
  auto grown = [&](Box2d box) {
    box.lo = box.lo - Vec2d{2 * eps_, 2 * eps_};
    box.hi = box.hi + Vec2d{2 * eps_, 2 * eps_};
    return box;
  };
  double t0, t1;
  if (nodes_.empty() || !ray_box_interval(ray, grown(nodes_[0].box), t0, t1)) {
    if (trace && !nodes_.empty()) trace->enter(0, label(0));
    return best;
  }
  stack[sp++] = {0, 0, t0};
  while (sp > 0) {
    const Entry e = stack[--sp];
    if (e.t0 > best.t) continue;
    if (trace) trace->enter(e.depth, label(e.node));
    const Node& n = nodes_[e.node];
    if (n.first_child == 0) {
      for (uint32_t k = n.first; k < n.first + n.count; ++k) {
        const uint32_t id = refs_[k];
        const double t = intersect(ray, segs_[id]);
        if (t < best.t || (t == best.t && t < INFINITY && id < best.id)) best.t = t, best.id = id;
      }
      continue;
    }
    // The children the ray meets, in order of entry (pushed last-first).
    Entry hits[4];
    int count = 0;
    for (uint32_t q = 0; q < 4; ++q) {
      double a, b;
      if (ray_box_interval(ray, grown(nodes_[n.first_child + q].box), a, b))
        hits[count++] = {n.first_child + q, e.depth + 1, a};
    }
    for (int i = 1; i < count; ++i)  // insertion sort of at most four entries
      for (int k = i; k > 0 && hits[k].t0 < hits[k - 1].t0; --k) std::swap(hits[k], hits[k - 1]);
    for (int i = count - 1; i >= 0; --i) stack[sp++] = hits[i];
  }
  if (trace && !best.hit()) trace->return_to(0);
  return best;
}

Stats2D Quadtree2D::stats() const {
  Stats2D s;
  s.nodes = nodes_.size();
  for (const Node& n : nodes_) s.leaves += n.first_child == 0;
  s.depth = depth_;
  s.fragments = refs_.size();
  s.build_ms = build_ms_;
  s.extra = {{"segments", double(segs_.size())}};
  return s;
}

Drawing2D Quadtree2D::draw(const Box2d& frame) const {
  Drawing2D d;
  d.frame = frame;
  for (uint32_t k = 0; k < nodes_.size(); ++k) {
    const Node& n = nodes_[k];
    const Box2d& b = n.box;
    if (n.first_child != 0) {
      // The two dividing lines, labelled with the node.
      const Vec2d mid = (b.lo + b.hi) * 0.5;
      d.lines.push_back({{{mid.x, b.lo.y}, {mid.x, b.hi.y}}, label(k)});
      d.lines.push_back({{{b.lo.x, mid.y}, {b.hi.x, mid.y}}, ""});
    } else {
      d.cells.push_back({{b.lo, {b.hi.x, b.lo.y}, b.hi, {b.lo.x, b.hi.y}}, label(k)});
    }
  }
  return d;
}

}  // namespace penumbra::lab2d
