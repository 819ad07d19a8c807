#include "penumbra/accel/build/bvh_builder.h"

#include <algorithm>

#include <oneapi/tbb/parallel_invoke.h>

namespace penumbra {

namespace {

/// Recursive builder into a scratch node array in which the subtree over references [b, e) owns
/// the 2 (e - b) - 2 slots after its own children: disjoint regions make the node indices (and so
/// the tree) independent of the order in which parallel tasks run. The root sits at 0 and slot 1
/// is padding, so every child pair starts at an even index. A final pass may compact it.
class Builder {
 public:
  Builder(const BvhBuildParams& p, PrimRef* refs, BvhNode* scratch)
      : p_(p), refs_(refs), nodes_(scratch) {}

  /// Leaves and depth of a finished subtree.
  struct Result {
    size_t leaves = 0, depth = 0;
  };

  /// Builds the subtree over refs [b, e) into node `node`, with descendants from slot `free`.
  Result build(uint32_t node, uint32_t b, uint32_t e, uint32_t free, const Bounds3& box,
               const Bounds3& centroids, int depth) {
    const uint32_t n = e - b;
    BvhNode& out = nodes_[node];
    out.set_bounds(box);
    if (n == 1) return make_leaf(out, b, n, depth);

    // Binned SAH split, unless the tree is already too deep.
    SahSplit split;
    // Fewer bins for small nodes: the sweep costs O(bins) whatever the node size.
    BinMapping map(centroids, std::min(p_.bins, std::max(4, int(n))));
    if (depth < kMaxSahDepth) split = find_binned_split({refs_ + b, n}, map, n >= p_.parallel_min);
    if (split.axis >= 0 && n <= uint32_t(p_.max_leaf)) {
      // Leaf cost n against traversal + SAH-weighted children, both scaled by the node's area.
      const float area = box.surface_area();
      if (float(n) * area <= p_.traversal_cost * area + split.cost)
        return make_leaf(out, b, n, depth);
    }
    if (split.axis < 0 && n <= uint32_t(p_.max_leaf)) return make_leaf(out, b, n, depth);

    // Partition, by the SAH split or else at the object median.
    uint32_t mid;
    Bounds3 lbox, rbox, lcen, rcen;
    if (split.axis >= 0) {
      mid = b + uint32_t(partition_refs({refs_ + b, n}, map, split, lcen, rcen));
      lbox = split.left, rbox = split.right;
    } else {
      mid = median_split(b, e, centroids);
      child_bounds(b, mid, lbox, lcen);
      child_bounds(mid, e, rbox, rcen);
    }

    // Children at (free, free + 1); their descendants in disjoint regions after them.
    out.index = free, out.count = 0;
    const uint32_t left_free = free + 2, right_free = left_free + 2 * (mid - b) - 2;
    Result l, r;
    auto build_left = [&] { l = build(free, b, mid, left_free, lbox, lcen, depth + 1); };
    auto build_right = [&] { r = build(free + 1, mid, e, right_free, rbox, rcen, depth + 1); };
    if (n >= p_.parallel_min) {
      tbb::parallel_invoke(build_left, build_right);
    } else {
      build_left();
      build_right();
    }
    return {l.leaves + r.leaves, std::max(l.depth, r.depth)};
  }

 private:
  Result make_leaf(BvhNode& out, uint32_t b, uint32_t n, int depth) {
    out.index = b, out.count = n;
    return {1, size_t(depth)};
  }

  /// Splits [b, e) in half along the widest centroid axis (ties broken by id, so deterministic);
  /// when all centroids coincide, just in half.
  uint32_t median_split(uint32_t b, uint32_t e, const Bounds3& centroids) {
    const uint32_t mid = b + (e - b) / 2;
    const int a = centroids.max_extent_axis();
    if (!(centroids.diagonal()[a] > 0.0f)) return mid;
    std::nth_element(refs_ + b, refs_ + mid, refs_ + e, [a](const PrimRef& x, const PrimRef& y) {
      const float cx = x.centroid2()[a], cy = y.centroid2()[a];
      return cx < cy || (cx == cy && x.id < y.id);
    });
    return mid;
  }

  void child_bounds(uint32_t b, uint32_t e, Bounds3& box, Bounds3& centroids) const {
    for (uint32_t i = b; i < e; ++i)
      box.extend(refs_[i].bounds()), centroids.extend(refs_[i].centroid2());
  }

  const BvhBuildParams& p_;
  PrimRef* refs_;
  BvhNode* nodes_;
};

/// Copies the scratch tree into a dense array: root, padding, then child pairs in depth-first
/// order (a pair's subtree follows it closely, which suits near-first traversal).
BvhNodeArray compact(const BvhNode* scratch, size_t leaves) {
  BvhNodeArray out(2 * leaves);  // root + padding + (leaves - 1) pairs
  out[0] = scratch[0];
  out[1] = BvhNode{{0, 0, 0, 0, 0, 0}, 0, 0};
  std::vector<uint32_t> stack{0};
  uint32_t next = 2;
  while (!stack.empty()) {
    const uint32_t k = stack.back();
    stack.pop_back();
    if (out[k].is_leaf()) continue;
    const uint32_t src = out[k].index;
    out[next] = scratch[src], out[next + 1] = scratch[src + 1];
    out[k].index = next;
    stack.push_back(next + 1);
    stack.push_back(next);
    next += 2;
  }
  return out;
}

}  // namespace

BvhBuildParams read_bvh_build_params(const ParamList& params) {
  BvhBuildParams p;
  p.max_leaf = int(params.get_int("leaf", p.max_leaf, 1, 64));
  p.bins = int(params.get_int("bins", p.bins, 2, kMaxBins));
  p.traversal_cost = float(params.get_real("trav", p.traversal_cost, 0.0, 100.0));
  return p;
}

BinaryBvh build_binary_bvh(PrimRefs in, const BvhBuildParams& params, bool compact_nodes) {
  BinaryBvh out;
  out.refs = std::move(in.refs);
  const auto n = static_cast<uint32_t>(out.refs.size());
  if (n == 0) return out;
  // Scratch nodes: the build writes every slot it later reads.
  BvhNodeArray scratch(2 * size_t(n));
  scratch[1] = BvhNode{{0, 0, 0, 0, 0, 0}, 0, 0};
  Builder builder(params, out.refs.data(), scratch.data());
  const Builder::Result r = builder.build(0, 0, n, 2, in.bounds, in.centroid_bounds, 0);
  out.leaves = r.leaves;
  out.max_depth = r.depth;
  out.nodes = compact_nodes ? compact(scratch.data(), r.leaves) : std::move(scratch);
  return out;
}

}  // namespace penumbra
