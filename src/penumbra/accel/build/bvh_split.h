#pragma once
/// What a BVH split strategy (binned SAH, full-sweep SAH, object median) tells the top-down
/// builder about one node: make it a leaf, or where its references divide and the children's
/// boxes. The builder (bvh_builder.cpp) owns the node layout, the recursion and the parallelism.
#include <cstdint>

#include "penumbra/core/bounds.h"

namespace penumbra {

/// The decision for a node over references [b, e): a leaf, or children [b, mid) and [mid, e)
/// (or [mid, end) after a spatial split).
struct NodeSplit {
  bool leaf = false;        ///< make the node a leaf (the other fields are then unused)
  uint32_t mid = 0;         ///< first reference of the right child (absolute index)
  /// One past the right child's last reference when the split added references (a spatial
  /// split writes its two sides over [b, end), end within the node's capacity); 0 means e.
  uint32_t end = 0;
  /// The children may still split spatially (the builder gives them room for more references);
  /// false where this node's spatial split was far from paying, or never tried.
  bool room = false;
  Bounds3 left, right;      ///< boxes of the two children
  Bounds3 left_centroids;   ///< bounds of centroid2() over the left child
  Bounds3 right_centroids;  ///< bounds of centroid2() over the right child

  /// The decision to make a leaf.
  static NodeSplit make_leaf() {
    NodeSplit s;
    s.leaf = true;
    return s;
  }
};

/// The SAH's count of intersection tests for `n` references in a leaf tested 2^block_shift at a
/// time (SIMD blocks: ceil(n / 2^block_shift); n itself for block_shift = 0).
inline float sah_tests(uint32_t n, int block_shift) {
  return float((uint64_t(n) + (uint64_t(1) << block_shift) - 1) >> block_shift);
}

/// The SAH termination test (Goldsmith & Salmon 1987, "Automatic Creation of Object Hierarchies
/// for Ray Tracing"; MacDonald & Booth 1990): a leaf of `n` references costs sah_tests(n), a
/// split `traversal_cost` plus its cost `split_cost` = area(L) T(L) + area(R) T(R), both relative
/// to the area of the node's `box`. True when the leaf is no dearer.
inline bool sah_prefers_leaf(uint32_t n, const Bounds3& box, float split_cost,
                             float traversal_cost, int block_shift = 0) {
  const float area = box.surface_area();
  return sah_tests(n, block_shift) * area <= traversal_cost * area + split_cost;
}

}  // namespace penumbra
