#include "penumbra/accel2d/line_tree.h"

#include <iterator>

#include <fmt/format.h>

#include "penumbra/geometry/convex_polygon2d.h"

namespace penumbra::lab2d {

uint32_t LineTree::add(LineNode node, bool internal_node) {
  if (internal_node) node.number = uint32_t(++internal);
  nodes.push_back(node);
  return uint32_t(nodes.size() - 1);
}

std::string LineTree::label(uint32_t node) const {
  const LineNode& n = nodes[node];
  if (!n.leaf()) return fmt::format("l{}", n.number);
  if (n.count == 0) return "empty";
  std::string s;
  for (uint32_t k = n.first; k < n.first + n.count; ++k)
    fmt::format_to(std::back_inserter(s), "{}{}{}", k == n.first ? "" : ",", leaf_prefix,
                   refs[k] + 1);
  return s;
}

Stats2D line_tree_stats(const LineTree& tree, double build_ms) {
  Stats2D s;
  s.nodes = tree.nodes.size();
  s.leaves = s.nodes - tree.internal;
  s.depth = tree.depth;
  s.fragments = tree.refs.size();
  s.build_ms = build_ms;
  return s;
}

Drawing2D draw_line_tree(const LineTree& tree, const Box2d& frame) {
  Drawing2D d;
  d.frame = frame;
  if (tree.nodes.empty()) return d;
  struct Job {
    uint32_t node;
    std::vector<Vec2d> cell;
  };
  std::vector<Job> jobs;
  jobs.push_back({0, {frame.lo, {frame.hi.x, frame.lo.y}, frame.hi, {frame.lo.x, frame.hi.y}}});
  while (!jobs.empty()) {
    Job job = std::move(jobs.back());
    jobs.pop_back();
    const LineNode& n = tree.nodes[job.node];
    if (n.leaf()) {
      d.cells.push_back({job.cell, tree.label(job.node)});
      continue;
    }
    // The line within the cell; then each side's cell (a side may vanish outside the frame).
    Segment2 chord;
    if (clip_line(job.cell, n.line, chord)) d.lines.push_back({chord, tree.label(job.node)});
    for (int side = 1; side >= 0; --side) {
      std::vector<Vec2d> part = clip_convex(job.cell, n.line, side == 0, 0.0);
      if (part.size() >= 3) jobs.push_back({n.child[side], std::move(part)});
    }
  }
  return d;
}

}  // namespace penumbra::lab2d
