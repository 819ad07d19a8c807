#pragma once
/// Treelet restructuring of a binary BVH (Karras & Aila 2013, "Fast Parallel Construction of
/// High-Quality Bounding Volume Hierarchies", section 4): each inner node and the up to seven
/// subtrees below it that have the largest surface areas form a treelet, whose topology is
/// replaced by the one of least SAH cost among all binary trees over those subtrees (dynamic
/// programming over the subsets). The subtrees below the treelet, and so the leaves, their
/// references and the tree's leaf costs, are kept; only the inner nodes above them move, and
/// their boxes become the unions of their subtrees' boxes.
#include <cstddef>

#include "penumbra/accel/build/bvh_node.h"

namespace penumbra {

/// What an optimisation did.
struct TreeletStats {
  size_t treelets = 0;     ///< treelets rebuilt with another topology
  double area_before = 0;  ///< sum of the inner nodes' surface areas before, over the root's
  double area_after = 0;   ///< the same after
  size_t max_depth = 0;    ///< deepest leaf after (root at 0)
};

/// Restructures the binary tree in `nodes` (root at 0, inner nodes' children as adjacent pairs,
/// as build_binary_bvh makes it) in `passes` bottom-up passes, each treelet rooted at every
/// inner node once per pass, children before parents; the subtrees below depth 8 run as
/// parallel tasks, and the tree is the same at any thread count. A treelet is
/// rewritten only when its new topology's inner areas sum to less than the old one's (both with
/// the boxes as unions of the treelet's subtrees). Pairs keep their places in the array, so a
/// pair stays on one cache line.
TreeletStats optimize_treelets(BvhNodeArray& nodes, int passes);

}  // namespace penumbra
