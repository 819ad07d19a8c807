#pragma once
/// The flat binary BVH node (32 bytes, two to a cache line) and the aligned array that holds them.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "penumbra/core/array_allocator.h"
#include "penumbra/core/bounds.h"
#include "penumbra/geometry/hit.h"

namespace penumbra {

/// A node of a binary BVH. The box is stored as (lo.x, hi.x, lo.y, hi.y, lo.z, hi.z) so that the
/// slab test can index the near and far planes as box[2 * axis + sign] with the ray's direction
/// signs (Williams et al. 2005, "An Efficient and Robust Ray-Box Intersection Algorithm").
/// The two children of an inner node are adjacent and start at an even index, so a pair fills one
/// 64-byte cache line.
struct alignas(32) BvhNode {
  float box[6];    ///< lo.x, hi.x, lo.y, hi.y, lo.z, hi.z
  uint32_t index;  ///< inner node: first of the two children; leaf: first primitive (leaf order)
  uint32_t count;  ///< primitives in a leaf; 0 marks an inner node

  /// True for a leaf.
  bool is_leaf() const { return count != 0; }
  /// The box as Bounds3.
  Bounds3 bounds() const { return {{box[0], box[2], box[4]}, {box[1], box[3], box[5]}}; }
  /// Sets the box from a Bounds3.
  void set_bounds(const Bounds3& b) {
    box[0] = b.lo.x, box[1] = b.hi.x, box[2] = b.lo.y, box[3] = b.hi.y, box[4] = b.lo.z,
    box[5] = b.hi.z;
  }
};
static_assert(sizeof(BvhNode) == 32);

/// Grows a box (rows as BvhNode::box) on every side by kCullSlack (geometry/hit.h) of its largest
/// extent, rounded outward, for the boxes a traversal tests: with culling at cull_bound(hit.t),
/// this covers the part of a primitive's t error that scales with its size, so that a box is
/// not passed over because that t rounds below the box's entry (hit.h). Empty boxes (lo > hi, or
/// NaN) stay as they are, and no plane goes beyond the largest finite float.
inline void grow_box(float* box) {
  for (int a = 0; a < 3; ++a)
    if (!(box[2 * a] <= box[2 * a + 1])) return;
  double extent = 0;
  for (int a = 0; a < 3; ++a)
    extent = std::max(extent, double(box[2 * a + 1]) - double(box[2 * a]));
  const double slack = extent * double(kCullSlack);
  constexpr float kMax = std::numeric_limits<float>::max();
  for (int a = 0; a < 3; ++a) {
    const double lo = double(box[2 * a]) - slack, hi = double(box[2 * a + 1]) + slack;
    float l = static_cast<float>(std::max(lo, double(-kMax)));
    float h = static_cast<float>(std::min(hi, double(kMax)));
    if (double(l) > lo) l = std::nextafter(l, -kMax);
    if (double(h) < hi) h = std::nextafter(h, kMax);
    box[2 * a] = l, box[2 * a + 1] = h;
  }
}

/// Node array: starts on a cache line, huge pages when large; sizing it writes nothing (the
/// builders write every node that is read).
using BvhNodeArray = std::vector<BvhNode, NoInitArrayAllocator<BvhNode>>;

/// grow_box on every node reachable from the root (nodes[0]) of a binary tree.
inline void grow_boxes(BvhNodeArray& nodes) {
  if (nodes.empty()) return;
  std::vector<uint32_t> todo{0};
  while (!todo.empty()) {
    BvhNode& n = nodes[todo.back()];
    todo.pop_back();
    grow_box(n.box);
    if (!n.is_leaf()) todo.push_back(n.index), todo.push_back(n.index + 1);
  }
}

}  // namespace penumbra
