#include "penumbra/accel/build/bvh_builder.h"

#include <algorithm>
#include <atomic>
#include <string>

#include <fmt/format.h>
#include <oneapi/tbb/parallel_invoke.h>

#include "penumbra/accel/build/bvh_median.h"
#include "penumbra/accel/build/bvh_split.h"
#include "penumbra/accel/build/bvh_sweep.h"
#include "penumbra/accel/build/kd_clip.h"
#include "penumbra/accel/build/spatial_split.h"
#include "penumbra/core/error.h"

namespace penumbra {

namespace {

/// Spatial splits, tuned on cylinder_engine and the terrain (docs/accel.md, "Spatial splits"):
/// a node's spatial split is estimated from at most this many of its references;
constexpr size_t kSpatialSamples = 4096;
/// it is made only when the estimate is below this fraction of the object split's cost (the
/// sample's boxes are a little smaller than the whole set's, so near ties are mostly false) and
/// the cost over all references confirms it;
constexpr float kSpatialMargin = 0.97f;
/// and the children get room for more references only when the estimate was within this factor
/// of the object split's cost (a subtree far from splitting spatially stays compact in memory),
constexpr float kSpatialRoom = 1.25f;
/// and only when the estimated split duplicates some references (its straddlers; one that
/// duplicates none is an object split, which needs no room), more than this fraction of the
/// node's unless the estimate is below the object split's cost. With fewer, the node's
/// primitives are small against it, as in a height field's upper levels: there the estimate sits
/// within a few per cent of the object split's and never beats it by the margin, and the room
/// only cost moves of the right child's references, about half of the node's at every level,
/// and spatial searches in every subtree below (docs/accel.md, "2026-12-07, twenty-sixth
/// session": the 1M-triangle terrain's build; cylinder_engine's SAH cost 30.073 -> 30.094).
constexpr float kRoomStraddlers = 0.02f;

/// Nodes of fewer references than this are binned with at most `few_bins` bins.
constexpr uint32_t kFewBinsBelow = 256;

/// The binned SAH strategy: Wald 2007, with the object median where no bin boundary separates
/// the references or the tree is too deep; with `prims`, also spatial splits (spatial_split.h).
struct BinnedSplitter {
  const BvhBuildParams& p;
  PrimRef* refs;
  const PrimitiveSet* prims = nullptr;  ///< set when spatial splits are on
  float min_overlap = 0.0f;             ///< alpha times the root's surface area

  /// The split of the node over [b, e), whose references may grow up to `cap`.
  NodeSplit operator()(uint32_t b, uint32_t e, uint32_t cap, const Bounds3& box,
                       const Bounds3& centroids, int depth) const {
    const uint32_t n = e - b;
    // A split costs at least the traversal step, so a leaf that costs no more than that is
    // chosen by the SAH test below whatever the split: no need to bin it (on a million
    // triangles in blocks of four with traversal cost 2, a tenth of the binning time).
    if (n <= uint32_t(p.max_leaf) && sah_tests(n, p.block_shift) <= p.traversal_cost)
      return NodeSplit::make_leaf();
    SahSplit split;
    // Fewer bins for small nodes: the sweep costs O(bins) whatever the node size.
    const int bins = n < kFewBinsBelow && p.few_bins > 0 ? std::min(p.bins, p.few_bins) : p.bins;
    BinMapping map(centroids, std::min(bins, std::max(4, int(n))));
    // Small nodes: the exact SAH, which leaves [b, e) sorted along its axis, left side first.
    const bool exact = n <= uint32_t(p.exact_below) && depth < kMaxSahDepth;
    if (exact)
      split = find_exact_split({refs + b, n}, p.block_shift);
    else if (depth < kMaxSahDepth)
      split = find_binned_split({refs + b, n}, map, n >= p.parallel_min, p.block_shift);
    // A spatial split where the object split's children overlap (or none separates them) and
    // the node has room for more references.
    SpatialSplit spatial;
    bool room = false;
    if (prims && cap > e && depth < kMaxSahDepth &&
        (split.axis < 0 || intersect_boxes(split.left, split.right).surface_area() > min_overlap)) {
      spatial = find_spatial_split({refs + b, n}, box, p.bins, kSpatialSamples, p.block_shift);
      const bool better = spatial.cost < split.cost;
      const bool near = spatial.cost < kSpatialRoom * split.cost;
      room = spatial.axis >= 0 && (split.axis < 0 || (better && spatial.straddlers > 0.0f) ||
                                   (near && spatial.straddlers > kRoomStraddlers * float(n)));
      // The sample's estimate, when clearly better, is checked against all references before
      // the split is made.
      if (spatial.axis >= 0 && split.axis >= 0 &&
          !(spatial.cost < kSpatialMargin * split.cost &&
            spatial_split_cost({refs + b, n}, spatial, p.block_shift) < split.cost))
        spatial.axis = -1;
    }
    const bool any = split.axis >= 0 || spatial.axis >= 0;
    const float cost = spatial.axis >= 0 ? spatial.cost : split.cost;
    if (n <= uint32_t(p.max_leaf) &&
        (!any || sah_prefers_leaf(n, box, cost, p.traversal_cost, p.block_shift)))
      return NodeSplit::make_leaf();
    if (spatial.axis >= 0) {
      SpatialSides sides;
      apply_spatial_split(*prims, {refs + b, n}, spatial, sides);
      const size_t nl = sides.left.size(), nr = sides.right.size();
      // Unsplitting and empty parts may leave one side empty; the node's capacity bounds the
      // growth. Otherwise the object split below.
      const float made = sides.left_box.surface_area() * sah_tests(uint32_t(nl), p.block_shift) +
                         sides.right_box.surface_area() * sah_tests(uint32_t(nr), p.block_shift);
      if (nl > 0 && nr > 0 && nl + nr <= size_t(cap - b) && (split.axis < 0 || made < split.cost)) {
        std::copy(sides.left.begin(), sides.left.end(), refs + b);
        std::copy(sides.right.begin(), sides.right.end(), refs + b + nl);
        NodeSplit s;
        s.mid = b + uint32_t(nl), s.end = b + uint32_t(nl + nr);
        s.left = sides.left_box, s.right = sides.right_box;
        s.left_centroids = sides.left_centroids, s.right_centroids = sides.right_centroids;
        s.room = true;
        return s;
      }
    }
    if (split.axis < 0) {
      NodeSplit s = object_median_split({refs + b, n}, b, centroids);
      s.room = room;
      return s;
    }
    NodeSplit s;
    s.room = room;
    if (exact) {
      s.mid = b + split.left_count;
      for (uint32_t i = b; i < e; ++i)
        (i < s.mid ? s.left_centroids : s.right_centroids).extend(refs[i].centroid2());
    } else {
      s.mid = b + uint32_t(partition_refs({refs + b, n}, map, split, s.left_centroids,
                                          s.right_centroids));
    }
    s.left = split.left, s.right = split.right;
    return s;
  }
};

/// Recursive builder into a scratch node array. Child pairs take slots from a shared counter in
/// the order the build reaches them; a subtree of fewer than `parallel_min` references builds
/// serially into a per-thread buffer and then takes one run of slots for all its nodes. So only
/// as many slots are written as the tree has nodes: the scratch array's bound (2 per reference)
/// is virtual memory, mostly never touched. Regions fixed per subtree (2 slots per reference of
/// each) made the tree's node indices independent of task order, but spread a tree of about a
/// quarter of that many nodes over all of it, and every huge page of it was faulted in and zeroed
/// (on the 1M-triangle terrain with spatial room, 128 MB for 16: a fifth of the binary build).
/// The slots now depend on the order in which tasks finish; the tree itself (structure, boxes,
/// leaf ranges of the references) does not, and compact() or a walk from the root (the wide
/// collapse) gives the same result at any thread count. The root sits at 0 and slot 1 is
/// padding, and runs of slots have even lengths, so every child pair starts at an even index.
/// `Split` decides each node (a NodeSplit from its range, box, centroid bounds and depth) and
/// reorders the references; it is called concurrently on disjoint ranges.
template <class Split>
class Builder {
 public:
  /// `room_area`: a subtree whose box has no more surface area than this never tries a spatial
  /// split, so it gets no room for more references (+infinity when spatial splits are off).
  Builder(const BvhBuildParams& p, Split& split, BvhNode* scratch, PrimRef* refs, float room_area)
      : p_(p), split_(split), nodes_(scratch), refs_(refs), room_area_(room_area) {}

  /// Leaves and depth of a finished subtree.
  struct Result {
    size_t leaves = 0, depth = 0;
  };

  /// Builds the subtree over refs [b, e) into node `node` of the scratch array. The subtree may
  /// grow its references (spatial splits) up to `cap` (>= e).
  Result build(uint32_t node, uint32_t b, uint32_t e, uint32_t cap, const Bounds3& box,
               const Bounds3& centroids, int depth) {
    if (e - b < p_.parallel_min) return build_serial(node, b, e, cap, box, centroids, depth);
    BvhNode& out = nodes_[node];
    Result l, r;
    const auto children = [&](const NodeSplit& s, const Span& left, const Span& right) {
      const auto kids = next_.fetch_add(2, std::memory_order_relaxed);
      tbb::parallel_invoke(
          [&] { l = build(kids, left.b, left.e, left.cap, s.left, s.left_centroids, depth + 1); },
          [&] {
            r = build(kids + 1, right.b, right.e, right.cap, s.right, s.right_centroids, depth + 1);
          });
      return kids;
    };
    if (!node_step(out, b, e, cap, box, centroids, depth, children)) return {1, size_t(depth)};
    return {l.leaves + r.leaves, std::max(l.depth, r.depth)};
  }

 private:
  /// A child's references: [b, e), room up to cap.
  struct Span {
    uint32_t b, e, cap;
  };

  /// Splits the node over [b, e) into `out`: a leaf (returns false), or an inner node whose
  /// children `children(split, left, right)` builds, returning the slot of the pair.
  template <class Children>
  bool node_step(BvhNode& out, uint32_t b, uint32_t e, uint32_t cap, const Bounds3& box,
                 const Bounds3& centroids, int depth, const Children& children) {
    const uint32_t n = e - b;
    out.set_bounds(box);
    if (n == 1) {
      out.index = b, out.count = n;
      return false;
    }
    const NodeSplit s = split_(b, e, cap, box, centroids, depth);
    if (s.leaf) {
      out.index = b, out.count = n;
      return false;
    }
    // The room left for more references goes to the children that may still split spatially,
    // shared in proportion to their sizes (as Embree's spatial-split builder does); the right
    // one's references move up. A child too small to split spatially gets none: its subtree
    // stays compact, and the memory it would have spread over is never touched.
    const uint32_t mid = s.mid, end = s.end ? s.end : e;
    const uint32_t right_count = end - mid;
    uint32_t left_cap = mid, right_cap = mid + right_count;
    if (cap > end) {
      const bool left_room = s.room && s.left.surface_area() > room_area_;
      const bool right_room = s.room && s.right.surface_area() > room_area_;
      const uint64_t slack = cap - end, nl = mid - b;
      if (left_room) left_cap += uint32_t(right_room ? slack * nl / (nl + right_count) : slack);
      right_cap = right_room ? cap : left_cap + right_count;
      if (left_cap != mid)
        std::copy_backward(refs_ + mid, refs_ + end, refs_ + left_cap + right_count);
    }
    out.count = 0;
    out.index =
        children(s, Span{b, mid, left_cap}, Span{left_cap, left_cap + right_count, right_cap});
    return true;
  }

  /// Nodes of a serial subtree, indexed from 0: its root, padding, then child pairs.
  using Local = std::vector<BvhNode, NoInitArrayAllocator<BvhNode>>;

  /// Builds the subtree under `node` serially in a buffer, then copies its nodes below the root
  /// to one run of scratch slots.
  Result build_serial(uint32_t node, uint32_t b, uint32_t e, uint32_t cap, const Bounds3& box,
                      const Bounds3& centroids, int depth) {
    // One buffer per thread, reused from subtree to subtree (its capacity stays). The guard
    // gives a nested use (none is expected: the splits of small nodes start no tasks) its own.
    thread_local Local buffer;
    thread_local bool busy = false;
    Local own;
    Local& local = busy ? own : buffer;
    struct Claim {  // marks the buffer taken until the subtree is copied out (or throws)
      bool& flag;
      const bool before;
      ~Claim() { flag = before; }
    } claim{busy, busy};
    busy = true;
    local.assign(2, BvhNode{});  // the root (its parent's slot, copied out below) and padding
    const Result r = build_local(local, 0, b, e, cap, box, centroids, depth);
    const auto extra = static_cast<uint32_t>(local.size() - 2);  // even: pairs
    const uint32_t base = extra ? next_.fetch_add(extra, std::memory_order_relaxed) : 0;
    // Local pair slot i (>= 2) becomes scratch slot base + i - 2.
    const auto place = [&](BvhNode n) {
      if (!n.is_leaf()) n.index = n.index - 2 + base;
      return n;
    };
    nodes_[node] = place(local[0]);
    for (uint32_t i = 0; i < extra; ++i) nodes_[base + i] = place(local[2 + i]);
    return r;
  }

  /// The serial recursion into `local`, child pairs appended in depth-first order.
  Result build_local(Local& local, uint32_t node, uint32_t b, uint32_t e, uint32_t cap,
                     const Bounds3& box, const Bounds3& centroids, int depth) {
    Result l, r;
    const auto children = [&](const NodeSplit& s, const Span& left, const Span& right) {
      const auto kids = static_cast<uint32_t>(local.size());
      local.resize(kids + 2);
      l = build_local(local, kids, left.b, left.e, left.cap, s.left, s.left_centroids, depth + 1);
      r = build_local(local, kids + 1, right.b, right.e, right.cap, s.right, s.right_centroids,
                      depth + 1);
      return kids;
    };
    // Built in a copy: the recursion may reallocate `local`.
    BvhNode out;
    const bool inner = node_step(out, b, e, cap, box, centroids, depth, children);
    local[node] = out;
    if (!inner) return {1, size_t(depth)};
    return {l.leaves + r.leaves, std::max(l.depth, r.depth)};
  }

  const BvhBuildParams& p_;
  Split& split_;
  BvhNode* nodes_;
  PrimRef* refs_;
  float room_area_;
  std::atomic<uint32_t> next_{2};  ///< the next free scratch slot (root at 0, padding at 1)
};

/// Builds the tree over `n` references with `split` into `scratch`, from the root's box and
/// centroid bounds; sets the leaf count and depth of `out`.
template <class Split>
void build_tree(const BvhBuildParams& p, Split& split, uint32_t n, uint32_t cap, const PrimRefs& in,
                BvhNode* scratch, BinaryBvh& out, float room_area = kInfinity) {
  Builder<Split> builder(p, split, scratch, out.refs.data(), room_area);
  const auto r = builder.build(0, 0, n, cap, in.bounds, in.centroid_bounds, 0);
  out.leaves = r.leaves;
  out.max_depth = r.depth;
}

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

BvhBuildParams read_bvh_build_params(const ParamList& params, int default_leaf) {
  BvhBuildParams p;
  // build=METHOD, or the bare method name as a shorthand (as kdtree:sah).
  std::string method = params.get_string("build", "");
  for (const char* m : {"binned", "median", "sweep"}) {
    if (!params.has(m)) continue;
    if (!params.get_flag(m))
      throw Error(fmt::format("{}: build method '{}' cannot be false", params.name(), m));
    if (!method.empty() && method != m)
      throw Error(
          fmt::format("{}: give one build method (binned, median or sweep), got '{}' and '{}'",
                      params.name(), method, m));
    method = m;
  }
  if (method == "median")
    p.method = BvhSplitMethod::kMedian;
  else if (method == "sweep")
    p.method = BvhSplitMethod::kSweep;
  else if (!method.empty() && method != "binned")
    throw Error(fmt::format("{}: parameter 'build' must be binned, median or sweep, got '{}'",
                            params.name(), method));
  p.max_leaf = int(params.get_int("leaf", default_leaf, 1, 64));
  // Reject what the method would ignore rather than silently measuring something else.
  if (p.method != BvhSplitMethod::kBinned && params.has("bins"))
    throw Error(fmt::format("{}: parameter 'bins' applies only to build=binned", params.name()));
  if (p.method == BvhSplitMethod::kMedian && params.has("trav"))
    throw Error(
        fmt::format("{}: parameter 'trav' does not apply to build=median (no SAH)", params.name()));
  p.bins = int(params.get_int("bins", p.bins, 2, kMaxBins));
  if (p.method != BvhSplitMethod::kBinned && params.has("exact"))
    throw Error(fmt::format("{}: parameter 'exact' applies only to build=binned", params.name()));
  // exact=auto leaves the default: the caller's choice (WideBvh's depends on the set).
  if (params.get_string("exact", "auto") != "auto")
    p.exact_below = int(params.get_int("exact", p.exact_below, 0, kMaxExactSplit));
  p.traversal_cost = float(params.get_real("trav", p.traversal_cost, 0.0, 100.0));
  return p;
}

BinaryBvh build_binary_bvh(PrimRefs in, const BvhBuildParams& params, bool compact_nodes,
                           const PrimitiveSet* prims) {
  BinaryBvh out;
  out.refs = std::move(in.refs);
  const auto n = static_cast<uint32_t>(out.refs.size());
  if (n == 0) return out;
  const bool spatial =
      prims && params.method == BvhSplitMethod::kBinned && params.spatial_budget > 0.0f;
  if (spatial && !(params.spatial_budget <= 4.0f))
    throw Error("bvh: the spatial-split budget must lie in [0, 4]");
  if (spatial && !prims->all_triangles())
    throw Error("bvh: spatial splits need a set of static triangles");
  const uint32_t cap = spatial ? n + uint32_t(double(params.spatial_budget) * n) : n;
  out.refs.resize(cap);
  // Scratch nodes: the build writes every slot it later reads.
  BvhNodeArray scratch(2 * size_t(cap));
  scratch[1] = BvhNode{{0, 0, 0, 0, 0, 0}, 0, 0};
  PrimRef* refs = out.refs.data();
  switch (params.method) {
    case BvhSplitMethod::kBinned: {
      BinnedSplitter split{params, refs};
      if (spatial) {
        split.prims = prims;
        split.min_overlap = params.spatial_alpha * in.bounds.surface_area();
      }
      build_tree(params, split, n, cap, in, scratch.data(), out, split.min_overlap);
      break;
    }
    case BvhSplitMethod::kMedian: {
      MedianSplitter split{params, refs};
      build_tree(params, split, n, cap, in, scratch.data(), out);
      break;
    }
    case BvhSplitMethod::kSweep: {
      SweepSahSplitter split({refs, n}, params);
      build_tree(params, split, n, cap, in, scratch.data(), out);
      break;
    }
  }
  out.nodes = compact_nodes ? compact(scratch.data(), out.leaves) : std::move(scratch);
  return out;
}

}  // namespace penumbra
