#pragma once
/// The recursion shared by the kd-tree builders: a node is either a leaf or an inner node whose
/// below subtree follows it and whose above subtree comes after that (depth-first order).
#include <oneapi/tbb/parallel_invoke.h>

#include "penumbra/accel/build/kd_node.h"

namespace penumbra {

/// Builds the subtree of `node` into `out`. `split(node, depth, below, above)` chooses a plane
/// and fills the two children (leaving `node` empty), or returns axis < 0 with `node.prims`
/// intact to make a leaf. Children with `parallel_min` or more references in total are built as
/// parallel tasks into subtrees of their own that are then appended in order, so the tree does
/// not depend on the number of threads.
template <class Node, class Split>
void build_kd_subtree(Node& node, int depth, const Split& split, size_t parallel_min,
                      KdSubtree& out) {
  Node below, above;
  const KdPlane plane = split(node, depth, below, above);
  if (plane.axis < 0) {
    out.add_leaf(node.prims, depth);
    return;
  }
  const size_t self = out.nodes.size();
  out.nodes.push_back(KdNode::leaf(0, 0));  // replaced below once the above child's index is known
  size_t above_index;
  if (below.prims.size() + above.prims.size() >= parallel_min) {
    KdSubtree a, b;
    tbb::parallel_invoke([&] { build_kd_subtree(below, depth + 1, split, parallel_min, a); },
                         [&] { build_kd_subtree(above, depth + 1, split, parallel_min, b); });
    out.append(a);
    above_index = out.nodes.size();
    out.append(b);
  } else {
    build_kd_subtree(below, depth + 1, split, parallel_min, out);
    below = Node{};
    above_index = out.nodes.size();
    build_kd_subtree(above, depth + 1, split, parallel_min, out);
  }
  out.nodes[self] = KdNode::inner(plane.axis, plane.pos, uint32_t(above_index));
}

}  // namespace penumbra
