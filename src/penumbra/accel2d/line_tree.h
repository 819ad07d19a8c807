#pragma once
/// What the 2D trees split by lines share: the flat node, the front-to-back ray walk with its
/// trace, the labels, and the drawing of each line clipped to its cell. Used by the segment BSP,
/// the object BSP and the 2D kd-tree.
#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/accel2d/accel2d.h"

namespace penumbra::lab2d {

/// A node of a flat tree array (preorder, ℓ⁺ child first).
struct LineNode {
  static constexpr uint32_t kNone = 0xffffffffu;
  Line2 line;                          ///< the splitting line (internal nodes)
  uint32_t child[2] = {kNone, kNone};  ///< [0]: ℓ⁺ side, [1]: ℓ⁻ side; kNone in a leaf
  uint32_t first = 0, count = 0;       ///< shape references in ℓ (internal) or in the leaf
  uint32_t number = 0;                 ///< internal nodes: k of the label lk (preorder from 1)
  /// Bit 0 (ℓ⁺) and bit 1 (ℓ⁻): that side may hold a shape within 4 eps of the line. When it
  /// holds none, a hit in the line at the crossing ends the walk there (see shoot_line_tree).
  uint8_t touch = 3;
  /// True for a leaf.
  bool leaf() const { return child[0] == kNone; }
};

/// A built line tree: nodes (root first), the shape references they index, and its depth.
struct LineTree {
  std::vector<LineNode> nodes;
  std::vector<uint32_t> refs;
  size_t depth = 0;
  size_t internal = 0;
  char leaf_prefix = 's';  ///< leaves are labelled by their shapes: s3, O3, or s3,s7
  /// Appends a node, numbering internal ones in creation order; returns its index.
  uint32_t add(LineNode node, bool internal_node);
  /// "lk" for an internal node; a leaf's shapes ("s3", "O2,O5") or "empty".
  std::string label(uint32_t node) const;
};

/// The first hit of the ray walking the tree front to back: at a node, the side holding the ray's
/// start first; when the ray crosses the line, the shapes stored at the node, then the far side
/// (skipped once a hit lies before it). `hit_shape(id)` returns the ray parameter of the shape
/// (+inf on a miss). A line counts as crossed within 2 eps (a distance), so no cell the ray
/// touches is skipped; whole shapes are tested, so the answer is brute force's, bit for bit.
template <class HitShape>
Hit2 shoot_line_tree(const LineTree& tree, const Ray2& ray, double eps, HitShape&& hit_shape,
                     TraceLog* trace);

/// The splitting lines clipped to their cells, and the leaves' cells, within frame.
Drawing2D draw_line_tree(const LineTree& tree, const Box2d& frame);

/// The tree's size: nodes, leaves, depth, references as fragments, and `build_ms`.
Stats2D line_tree_stats(const LineTree& tree, double build_ms);

// ---- implementation ----

template <class HitShape>
Hit2 shoot_line_tree(const LineTree& tree, const Ray2& ray, double eps, HitShape&& hit_shape,
                     TraceLog* trace) {
  Hit2 best;
  if (tree.nodes.empty()) return best;
  struct Entry {
    uint32_t node, depth, test;  // test: the node whose shapes to test first (kNone: none)
    double t0, t1, skip;  // skip: a hit before this (in test's line) ends the far side's walk
  };
  // A fixed stack covers trees up to depth 126; deeper ones (adversarial orders) use the heap.
  constexpr size_t kStack = 128;
  Entry local[kStack];
  std::vector<Entry> heap;
  Entry* stack = local;
  if (tree.depth + 2 > kStack) {
    heap.resize(tree.depth + 2);
    stack = heap.data();
  }
  const double tol = 2 * eps;
  auto test_range = [&](const LineNode& n) {
    for (uint32_t k = n.first; k < n.first + n.count; ++k) {
      const uint32_t id = tree.refs[k];
      const double t = hit_shape(id);
      if (t < best.t || (t == best.t && t < INFINITY && id < best.id)) best.t = t, best.id = id;
    }
  };
  size_t sp = 0;
  stack[sp++] = {0, 0, LineNode::kNone, ray.tmin, ray.tmax, -INFINITY};
  while (sp > 0) {
    const Entry e = stack[--sp];
    if (e.t0 > best.t) continue;  // the cell begins beyond the closest hit
    if (e.test != LineNode::kNone) {
      // Back at the parent, the ray crosses its line: test the shapes stored in it.
      if (trace) trace->return_to(e.depth - 1);
      test_range(tree.nodes[e.test]);
      if (e.t0 > best.t || best.t <= e.skip) continue;
    }
    uint32_t node = e.node, depth = e.depth;
    double t0 = e.t0, t1 = e.t1;
    while (true) {
      if (trace) trace->enter(depth, tree.label(node));
      const LineNode& n = tree.nodes[node];
      if (n.leaf()) {
        test_range(n);
        break;
      }
      // Signed distance along the ray: s(t) = a0 + t ds.
      const double a0 = n.line.eval(ray.o), ds = n.line.a * ray.d.x + n.line.b * ray.d.y;
      auto s_at = [&](double t) {
        return std::isinf(t) ? (ds > 0 ? t : (ds < 0 ? -t : a0)) : a0 + t * ds;
      };
      const Side s0 = side_of(s_at(t0), tol), s1 = side_of(s_at(t1), tol);
      if (s0 == s1 && s0 != Side::kOn) {  // the whole interval on one side
        node = n.child[s0 == Side::kPositive ? 0 : 1];
        ++depth;
        continue;
      }
      // Both sides: near is the side of the start; a start in the line counts as on the side the
      // ray comes from (it crosses at tc ≈ t0 into the side it moves to).
      const int near = s0 == Side::kPositive ? 0 : (s0 == Side::kNegative ? 1 : (ds > 0 ? 1 : 0));
      double near_t1 = t1, far_t0 = t0, skip = -INFINITY;
      if (ds != 0 && !(s0 == Side::kOn && s1 == Side::kOn)) {
        const double tc = -a0 / ds, slack = tol / std::abs(ds);
        near_t1 = std::min(t1, tc + slack);
        far_t0 = std::max(t0, tc - slack);
        // With no shape of the far side within 4 eps = 2 tol of the line, the far side's hits lie
        // beyond tc + 2 slack: a hit in the line up to tc + slack wins, as in the lecture.
        if (!(n.touch & (near == 0 ? 2 : 1))) skip = tc + slack;
      }
      stack[sp++] = {n.child[1 - near], depth + 1, node, far_t0, t1, skip};
      node = n.child[near];
      ++depth;
      t1 = near_t1;
    }
  }
  if (trace && !best.hit()) trace->return_to(0);
  return best;
}

}  // namespace penumbra::lab2d
