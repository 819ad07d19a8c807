#include "penumbra/accel2d/object_bsp.h"

#include <fmt/format.h>

#include "penumbra/core/timer.h"
#include "penumbra/geometry/convex_polygon2d.h"

namespace penumbra::lab2d {

namespace {

/// An object's part inside the current cell.
struct Piece {
  uint32_t id;
  std::vector<Vec2d> poly;
};

/// Where a piece lies relative to a line: reaches ℓ⁺ and/or ℓ⁻ beyond eps; neither for a piece in
/// the line (a segment object on it), which goes to the side the line's score chose.
struct Reach {
  bool pos = false, neg = false;
};

Reach reach(const std::vector<Vec2d>& poly, const Line2& line, double eps) {
  Reach r;
  for (Vec2d p : poly) {
    const double d = line.eval(p);
    r.pos = r.pos || d > eps;
    r.neg = r.neg || d < -eps;
  }
  return r;
}

/// The piece of poly on one side; a segment object is clipped as a segment.
std::vector<Vec2d> clip_piece(const std::vector<Vec2d>& poly, const Line2& line, bool positive,
                              double eps) {
  if (poly.size() != 2) return clip_convex(poly, line, positive, eps);
  const double sign = positive ? 1.0 : -1.0;
  const double d0 = sign * line.eval(poly[0]), d1 = sign * line.eval(poly[1]);
  if (d0 >= 0 && d1 >= 0) return poly;
  const Vec2d x = lerp(poly[0], poly[1], d0 / (d0 - d1));
  return d0 >= 0 ? std::vector<Vec2d>{poly[0], x} : std::vector<Vec2d>{x, poly[1]};
}

}  // namespace

ObjectBsp::ObjectBsp(const ParamList& p)
    : candidates_(size_t(p.get_int("candidates", 64, 1, 1 << 20))) {
  p.check_all_used();
}

std::string ObjectBsp::name() const {
  return fmt::format("objects:candidates={}", candidates_);
}

void ObjectBsp::build(const Scene2D& scene) {
  const Timer timer;
  objects_.clear();
  for (const Shape2& s : scene.shapes) objects_.push_back(s.v);
  eps_ = scene.eps();
  tree_ = LineTree{};
  tree_.leaf_prefix = 'O';

  struct Job {
    std::vector<Piece> pieces;
    uint32_t parent;
    int side;
    uint32_t depth;
  };
  std::vector<Job> jobs(1);
  jobs[0].parent = LineNode::kNone;
  for (uint32_t k = 0; k < objects_.size(); ++k) jobs[0].pieces.push_back({k, objects_[k]});
  while (!jobs.empty()) {
    Job job = std::move(jobs.back());
    jobs.pop_back();
    tree_.depth = std::max<size_t>(tree_.depth, job.depth);
    const size_t m = job.pieces.size();
    // Score edge lines (spread evenly when there are more than `candidates`), then all of them
    // if none of the sample separates.
    std::vector<Line2> lines;
    for (const Piece& p : job.pieces) {
      const auto& v = objects_[p.id];
      const size_t edges = v.size() == 2 ? 1 : v.size();
      for (size_t e = 0; e < edges; ++e)
        lines.push_back(Line2::through(v[e], v[(e + 1) % v.size()]));
    }
    bool found = false;
    Line2 best;
    int on_side = 0;  // the side of the best line that takes the pieces in it
    if (m > 1) {
      size_t best_score = SIZE_MAX;
      auto score = [&](const Line2& line) {
        size_t only_pos = 0, only_neg = 0, cut = 0, on = 0;
        for (const Piece& p : job.pieces) {
          const Reach r = reach(p.poly, line, eps_);
          only_pos += r.pos && !r.neg;
          only_neg += r.neg && !r.pos;
          cut += r.pos && r.neg;
          on += !r.pos && !r.neg;
        }
        // Pieces in the line join the smaller side.
        const int side = only_pos <= only_neg ? 0 : 1;
        (side == 0 ? only_pos : only_neg) += on;
        if (only_pos == 0 || only_neg == 0) return;  // no progress on one side
        const size_t s =
            cut * (m + 1) + (only_pos > only_neg ? only_pos - only_neg : only_neg - only_pos);
        if (s < best_score) best_score = s, best = line, on_side = side, found = true;
      };
      const size_t step = std::max<size_t>(1, lines.size() / candidates_);
      for (size_t i = 0; i < lines.size(); i += step) score(lines[i]);
      if (!found)
        for (const Line2& line : lines) score(line);
    }
    LineNode node;
    uint32_t index;
    if (!found) {
      // A leaf: one object, none, or (touching objects no edge line separates) several.
      node.first = uint32_t(tree_.refs.size());
      for (const Piece& p : job.pieces) tree_.refs.push_back(p.id);
      node.count = uint32_t(m);
      index = tree_.add(node, false);
    } else {
      node.line = best;
      index = tree_.add(node, true);
      Job sides[2];
      for (Piece& p : job.pieces) {
        const Reach r = reach(p.poly, best, eps_);
        if (r.pos && r.neg) {
          sides[0].pieces.push_back({p.id, clip_piece(p.poly, best, true, eps_)});
          sides[1].pieces.push_back({p.id, clip_piece(p.poly, best, false, eps_)});
        } else {
          sides[r.pos ? 0 : (r.neg ? 1 : on_side)].pieces.push_back(std::move(p));
        }
      }
      for (int side = 1; side >= 0; --side) {  // ℓ⁺ on top: built first (preorder)
        sides[side].parent = index;
        sides[side].side = side;
        sides[side].depth = job.depth + 1;
        jobs.push_back(std::move(sides[side]));
      }
    }
    if (job.parent != LineNode::kNone) tree_.nodes[job.parent].child[job.side] = index;
  }
  build_ms_ = timer.elapsed_ms();
}

Hit2 ObjectBsp::shoot(const Ray2& ray, TraceLog* trace) const {
  return shoot_line_tree(
      tree_, ray, eps_, [&](uint32_t id) { return intersect_polygon(ray, objects_[id]); }, trace);
}

Stats2D ObjectBsp::stats() const {
  Stats2D s = line_tree_stats(tree_, build_ms_);
  s.extra = {{"objects", double(objects_.size())}};
  return s;
}

Drawing2D ObjectBsp::draw(const Box2d& frame) const {
  return draw_line_tree(tree_, frame);
}

}  // namespace penumbra::lab2d
