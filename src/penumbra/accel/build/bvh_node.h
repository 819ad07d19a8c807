#pragma once
/// The flat binary BVH node (32 bytes, two to a cache line) and the aligned array that holds them.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/core/array_allocator.h"
#include "penumbra/core/bounds.h"

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

/// Node array: starts on a cache line, huge pages when large; sizing it writes nothing (the
/// builders write every node that is read).
using BvhNodeArray = std::vector<BvhNode, NoInitArrayAllocator<BvhNode>>;

}  // namespace penumbra
