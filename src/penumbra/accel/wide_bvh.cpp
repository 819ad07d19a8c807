#include "penumbra/accel/wide_bvh.h"

#include <algorithm>
#include <bit>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "penumbra/accel/build/bvh_sweep.h"
#include "penumbra/accel/build/presplit.h"
#include "penumbra/accel/build/treelet_opt.h"
#include "penumbra/accel/build/wide_collapse.h"
#include "penumbra/accel/build/wide_emit.h"
#include "penumbra/accel/prefetch.h"
#include "penumbra/accel/simd.h"
#include "penumbra/accel/small_sort.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/target.h"
#include "penumbra/core/timer.h"
#include "penumbra/geometry/float_error.h"

namespace penumbra {

using wide_build::Collapser;
using wide_build::dedupe_leaves;
using wide_build::wide_sah_cost;
using wide_build::WideNodeArray;

namespace {

/// Whether traverse() makes the leaf test's per-ray vectors (BlockRay) once per ray rather than
/// at each leaf: where the target has AVX-512's 32 vector registers, which hold them across the
/// loop beside the box test's.
#if defined(__AVX512F__)
constexpr bool kBlockRayPerRay = true;
#else
constexpr bool kBlockRayPerRay = false;
#endif

/// optimize=auto restructures the treelets of sets of at most this many primitives (one pass).
constexpr size_t kOptimizeBelow = size_t(1) << 18;

/// binleaf=auto merges leaves in the collapse of the 16-wide tree over sets of at most this many
/// primitives: small sets, whose tree stays in the caches, where the SAH's leaves are the faster
/// (the bunny's and human_blend's bounce rays +5-11 %); above, fewer and larger leaves (the
/// binary build's) are, as each node fetched is a cache miss (spheres-1m's incoherent rays -7 %
/// with merging, and half as much build time again).
constexpr size_t kMergeBelow = size_t(1) << 16;

/// Sets of at most this many primitives are built with and without spatial splits, and the tree
/// of lower wide SAH cost kept (a build of 4,096 triangles takes about a millisecond).
constexpr size_t kCompareBelow = 4096;

/// Row `row` of a node's child boxes, W lanes.
template <int W>
FloatW<W> plane(const WideNode<W>& n, int row) {
  return FloatW<W>::load(n.box[row]);
}
FloatW<8> plane(const CompressedNode& n, int row) {
  const int a = row >> 1;
  return FloatW<8>::from_u8(n.q[row]) * FloatW<8>::broadcast(n.step(a)) +
         FloatW<8>::broadcast(n.origin[a]);
}

/// Lanes that may hold a child (a full node's empty slots have empty boxes, never hit).
template <int W>
unsigned slots(const WideNode<W>&) {
  return (1u << W) - 1;
}
unsigned slots(const CompressedNode& n) {
  return n.valid;
}

/// Lanes that hold a leaf (a non-zero count).
template <class Node>
unsigned leaf_lanes(const Node& n) {
  unsigned m = 0;
  for (int i = 0; i < int(sizeof(n.count) / sizeof(n.count[0])); ++i)
    m |= unsigned(n.count[i] != 0) << i;
  return m;
}

/// The child an any-hit ray visits first among the children it hits (`mask`; `leaves`: those of
/// them that are leaves). A leaf when one is hit: a hit there ends the query with no node
/// fetched. Otherwise, with `span_order` (anyhit=span), the inner child whose box the ray
/// crosses over the longest span, the likeliest to hold a surface it hits; else the lowest lane
/// (anyhit=lanes). Nearest first, as closest-hit rays go, and sorting all of them by span cost
/// more than they saved (docs/accel.md, "2026-12-05, tenth session").
template <int W>
int any_hit_first(unsigned mask, unsigned leaves, FloatW<W> near, FloatW<W> far, bool span_order) {
  if (leaves) return std::countr_zero(leaves);
  int first = std::countr_zero(mask);
  if (span_order && (mask & (mask - 1))) {
    alignas(4 * W) float span[W];
    (far - near).store(span);
    for (unsigned m = mask & (mask - 1); m; m &= m - 1) {
      const int i = std::countr_zero(m);
      if (span[i] > span[first]) first = i;
    }
  }
  return first;
}

/// PreparedRay(r) out of line, for the interleaved batches: inlined into their slot setup,
/// GCC 12 stops with an internal compiler error (extract_insn, pass vregs) on its vectorised
/// std::signbit when compiling for x86-64-v3 since the culling of 2026-12-07 (hit.h, cull_bound).
[[gnu::noinline]] PreparedRay prepare_slot_ray(const Ray& r) {
  return PreparedRay(r);
}

}  // namespace

template <int W, class Node>
WideBvh<W, Node>::WideBvh(const ParamList& params) {
  // Leaves of up to 16 triangles (two eight-lane tests) in the 16-wide tree: fewer nodes and
  // levels for a few more triangles tested (docs/accel.md, "2026-12-06, twelfth session").
  params_ = read_bvh_build_params(params, W == 16 ? 16 : 8);
  const std::string collapse = params.get_string("collapse", "sah");
  if (collapse != "greedy" && collapse != "sah")
    throw Error(fmt::format("{}: parameter 'collapse' must be greedy or sah, got '{}'",
                            params.name(), collapse));
  sah_collapse_ = collapse == "sah";
  presplit_ = params.get_real("presplit", 0.0, 0.0, 4.0);
  // bins=N given: the 16-wide tree's default of 32 does not apply (build()).
  bins_given_ = params.has("bins");
  exact_below_ = params.get_string("exact", "auto") == "auto" ? -1 : params_.exact_below;
  // binleaf=auto: 8 in the 16-wide tree over sets of up to kMergeBelow primitives, where the
  // traversal waits on arithmetic more than on memory; no merging elsewhere. The greedy
  // collapse does not merge: rejected rather than ignored.
  bin_leaf_ = params.get_string("binleaf", "auto") == "auto"
                  ? -1
                  : int(params.get_int("binleaf", 0, 0, 64));
  if (!sah_collapse_ && bin_leaf_ > 0)
    throw Error(fmt::format("{}: parameter 'binleaf' needs collapse=sah", params.name()));
  // optimize=auto: one pass of treelet restructuring for sets of up to kOptimizeBelow
  // primitives, none above (where a pass gained 0-2 % for a third more build time, past
  // Embree's on spheres-1m at one thread; docs/accel.md).
  optimize_ = params.get_string("optimize", "auto") == "auto"
                  ? -1
                  : int(params.get_int("optimize", 0, 0, 16));
  const std::string order = params.get_string("order", "distance");
  if (order != "distance" && order != "octant")
    throw Error(fmt::format("{}: parameter 'order' must be distance or octant, got '{}'",
                            params.name(), order));
  if (order == "octant" && W != 8)
    throw Error(fmt::format("{}: order=octant needs width 8", params.name()));
  octant_order_ = order == "octant";
  // anyhit=auto: the span order on an Intel CPU (faster on the Intel Xeon measured, in its
  // AVX-512 and in AVX2 code) and on a CPU with AVX-512 (the Zen 4 measured, with whole-child
  // prefetches: occlusion +1-7 % on the three meshes where it stood at 1.0 x Embree, -2 to -4 %
  // on the two at 1.2-1.3), the lane order on others (faster on the Zen 2 measured); which is
  // faster depends on the core, not on the instruction set the code was compiled for
  // (docs/accel.md, "2026-12-05, tenth session", "2026-12-06, sixteenth session" and
  // "nineteenth session").
  const std::string anyhit = params.get_string("anyhit", "auto");
  if (anyhit != "auto" && anyhit != "span" && anyhit != "lanes")
    throw Error(fmt::format("{}: parameter 'anyhit' must be auto, span or lanes, got '{}'",
                            params.name(), anyhit));
  any_hit_span_ = anyhit == "auto" ? cpu_is_intel() || cpu_has_avx512() : anyhit == "span";
  const std::string interleave = params.get_string("interleave", "auto");
  if (interleave != "auto" && interleave != "on" && interleave != "off")
    throw Error(fmt::format("{}: parameter 'interleave' must be auto, on or off, got '{}'",
                            params.name(), interleave));
  interleave_mode_ = interleave == "on" ? 1 : interleave == "off" ? 0 : -1;
  const std::string prefetch = params.get_string("prefetch", "auto");
  if (prefetch != "auto" && prefetch != "whole" && prefetch != "line")
    throw Error(fmt::format("{}: parameter 'prefetch' must be auto, whole or line, got '{}'",
                            params.name(), prefetch));
  prefetch_mode_ = prefetch == "whole" ? 1 : prefetch == "line" ? 0 : -1;
  // Spatial splits are on by default for binned builds (budget 1: at most twice the references).
  const bool binned = params_.method == BvhSplitMethod::kBinned;
  params_.spatial_budget = float(params.get_real("spatial", binned ? 1.0 : 0.0, 0.0, 4.0));
  if (!binned && params_.spatial_budget > 0.0f)
    throw Error(fmt::format("{}: parameter 'spatial' applies only to build=binned", params.name()));
  if (params.has("alpha") && !(params_.spatial_budget > 0.0f))
    throw Error(
        fmt::format("{}: parameter 'alpha' needs spatial splits (spatial > 0)", params.name()));
  params_.spatial_alpha = float(params.get_real("alpha", params_.spatial_alpha, 0.0, 1.0));
  params.check_all_used();
  name_ = params.to_string();
}

template <int W, class Node>
void WideBvh<W, Node>::build(const PrimitiveSet& prims) {
  const Timer timer;
  prims_ = &prims;
  // The binary tree is only walked once, to collapse it: no need to compact it first.
  // Triangle leaves are tested four at a time (TriangleBlocks): let the SAH count blocks. The
  // 16-wide tree's leaves of up to 16 are tested as pairs of blocks (eight lanes): let it count
  // pairs there (2-5 % faster on the large meshes, within ±3 % on the small ones; docs/accel.md).
  BvhBuildParams params = params_;
  if (prims.all_triangles()) params.block_shift = W == 16 ? 3 : 2;
  // Spatial splits clip triangles, so only sets of static triangles get them; their room is
  // reserved with the references (growing the array would copy it).
  if (!prims.all_triangles()) params.spatial_budget = 0.0f;
  const bool presplit = presplit_ > 0 && prims.all_triangles();
  // The binary tree collapsed to W-wide nodes, with its references and wide SAH cost.
  struct Built {
    BinaryBvh tree;
    WideNodeArray<W> full;
    size_t leaves = 0, max_depth = 0;
    double sah_cost = 0;
    bool optimized = false;  // treelet restructuring ran: treelets rewritten, inner areas
    size_t treelets = 0;
    double area_before = 0, area_after = 0;
  };
  const auto build_wide = [&](const BvhBuildParams& bp) {
    Built b;
    const auto make_refs = [&] {
      PrimRefs refs =
          make_prim_refs(prims, size_t(double(bp.spatial_budget) * double(prims.size())) + 1);
      if (presplit) presplit_refs(prims, refs, presplit_);
      return refs;
    };
    // With leaves merged by the collapse, the binary build stops at smaller ones.
    BvhBuildParams bin_params = bp;
    const int bin_leaf = bin_leaf_ >= 0                           ? bin_leaf_
                         : W == 16 && prims.size() <= kMergeBelow ? 8
                                                                  : 0;
    const bool merge = sah_collapse_ && bin_leaf > 0 && bin_leaf < bp.max_leaf;
    if (merge) bin_params.max_leaf = bin_leaf;
    // exact=auto: where leaves merge (the small sets), nodes of up to 64 references are split
    // by the exact SAH rather than by bins, whose boundaries cannot make a side's count fill
    // its blocks (the bunny's incoherent rays +2 %, human_blend's +2 %; exact at every level
    // gave the bunny +4 % and human_blend -2 %; docs/accel.md, "2026-12-06, sixteenth session").
    if (merge && exact_below_ < 0) bin_params.exact_below = 64;
    // The 16-wide tree bins with 32 bins unless bins=N says otherwise: the finer splits lower
    // the wide SAH cost (the bunny 9.60 -> 9.41, spheres-1m 20.48 -> 20.30; incoherent rays +2 %
    // on the bunny, human_blend and spheres-1m, camera rays +1-2 % on spheres-1m). Above
    // kMergeBelow primitives, nodes of fewer than 256 references keep 16: there more cost
    // build time (spheres-1m about +10 % at two threads) and gained nothing (20.30 either way).
    if (W == 16 && !bins_given_) {
      bin_params.bins = 32;
      if (prims.size() > kMergeBelow) bin_params.few_bins = 16;
    }
    b.tree = build_binary_bvh(make_refs(), bin_params, false, &prims);
    const int passes = optimize_ >= 0 ? optimize_ : prims.size() <= kOptimizeBelow ? 1 : 0;
    if (passes > 0) {
      const TreeletStats st = optimize_treelets(b.tree.nodes, passes);
      b.optimized = true, b.treelets = st.treelets;
      b.area_before = st.area_before, b.area_after = st.area_after;
      b.tree.max_depth = st.max_depth;
      // Restructuring may deepen the tree; past what the traversal stack covers (never seen),
      // the tree is built again and left as built.
      if (st.max_depth >= size_t(kBvhStackSize)) {
        b = Built{};
        b.tree = build_binary_bvh(make_refs(), bin_params, false, &prims);
      }
    }
    const BinaryBvh& tree = b.tree;
    std::optional<SahCollapse> plan;
    if (sah_collapse_ && !tree.nodes.empty() && !tree.nodes[0].is_leaf())
      plan.emplace(tree.nodes, W, bp.traversal_cost, bp.block_shift,
                   merge ? uint32_t(bp.max_leaf) : 0u);
    Collapser<W> collapser(tree.nodes, b.full, plan ? &*plan : nullptr, octant_order_,
                           &b.tree.refs);
    if (!tree.nodes.empty()) {
      // At most one wide node per binary inner node: reserving that bound (only the pages
      // written are touched) and trimming afterwards costs a copy of the wide nodes, where
      // counting them first walked the plan a second time.
      b.full.reserve(tree.nodes[0].is_leaf() ? 1 : tree.leaves - 1);
      if (tree.nodes[0].is_leaf())
        collapser.emit_leaf_root(tree.nodes[0]);
      else if (plan && plan->merged(0))
        collapser.emit_merged_root();
      else
        collapser.emit(0, 0);
    }
    b.full.shrink_to_fit();
    if (presplit) dedupe_leaves<W>(b.full, b.tree.refs);
    b.leaves = collapser.leaves(), b.max_depth = collapser.max_depth();
    b.sah_cost = wide_sah_cost(b.full, bp.traversal_cost, bp.block_shift);
    return b;
  };
  Built best = build_wide(params);
  // The spatial splits' gain is judged node by node on the binary tree; a small scene that
  // fits in a few wide nodes can come out dearer once collapsed (the Cornell box: wide SAH cost
  // 7.19 against 5.70 without them). Small sets are cheap to build twice: keep the cheaper.
  if (params.spatial_budget > 0.0f && prims.size() <= kCompareBelow) {
    BvhBuildParams plain = params;
    plain.spatial_budget = 0.0f;
    Built other = build_wide(plain);
    if (other.sah_cost <= best.sah_cost) best = std::move(other);
  }
  BinaryBvh& tree = best.tree;
  WideNodeArray<W>& full = best.full;
  const double sah_cost = best.sah_cost;
  // The references in leaves (spatial splits leave unused slots in tree.refs).
  size_t leaf_refs = 0;
  for (const WideNode<W>& n : full)
    for (int i = 0; i < W; ++i) leaf_refs += n.count[i];

  leaf_ = LeafPrims{};
  blocks_.resize(0);
  if (prims.all_triangles()) {
    make_blocks(full, prims, tree.refs);
  } else {
    // Only the leaves' references, in node order (LeafPrims copies every slot it is given;
    // merged leaves left their originals behind).
    PrimRefArray packed;
    packed.reserve(leaf_refs);
    for (WideNode<W>& n : full)
      for (int i = 0; i < W; ++i) {
        if (n.count[i] == 0) continue;
        const auto first = static_cast<uint32_t>(packed.size());
        packed.insert(packed.end(), tree.refs.begin() + n.child[i],
                      tree.refs.begin() + n.child[i] + n.count[i]);
        n.child[i] = first;
      }
    leaf_.build(prims, packed);
  }
  if constexpr (std::is_same_v<Node, WideNode<W>>) {
    nodes_ = std::move(full);
  } else {
    nodes_.clear();
    nodes_.resize(full.size());
    parallel_for_range(
        full.size(),
        [&](size_t begin, size_t end) {
          for (size_t i = begin; i < end; ++i) nodes_[i] = compress_node(full[i]);
        },
        4096);
  }
  stats_ = {};
  stats_.nodes = nodes_.size() + best.leaves;
  stats_.leaves = best.leaves;
  stats_.max_depth = best.max_depth;
  stats_.prim_refs = leaf_refs;
  stats_.bytes = nodes_.capacity() * sizeof(Node) + leaf_.bytes() + blocks_.bytes();
  stats_.extra = {{"width", double(W)}, {"sah_cost", sah_cost}};
  interleave_ = interleave_mode_ < 0 ? stats_.bytes > kInterleaveBytes : interleave_mode_ == 1;
  stats_.extra.emplace_back("interleaved batches", double(interleave_));
  prefetch_whole_ = prefetch_mode_ < 0 ? stats_.bytes > kPrefetchWholeBytes : prefetch_mode_ == 1;
  stats_.extra.emplace_back("prefetch whole", double(prefetch_whole_));
  stats_.extra.emplace_back("anyhit span", double(any_hit_span_));
  if (best.optimized) {
    stats_.extra.emplace_back("treelets rewritten", double(best.treelets));
    stats_.extra.emplace_back("inner area before", best.area_before);
    stats_.extra.emplace_back("inner area after", best.area_after);
  }
  stats_.build_ms = timer.elapsed_ms();
}

template <int W, class Node>
void WideBvh<W, Node>::make_blocks(std::span<WideNode<W>> nodes, const PrimitiveSet& prims,
                                   std::span<const PrimRef> refs) {
  // Leaf children in node order (depth first), each given its first block: the blocks of
  // nearby leaves lie close in memory, as their references did.
  std::vector<uint32_t> leaf_lanes;  // node * W + lane
  for (size_t n = 0; n < nodes.size(); ++n)
    for (int i = 0; i < W; ++i)
      if (nodes[n].count[i] > 0) leaf_lanes.push_back(static_cast<uint32_t>(n * W + i));
  std::vector<uint32_t> first(leaf_lanes.size() + 1, 0);
  for (size_t l = 0; l < leaf_lanes.size(); ++l) {
    const uint32_t count = nodes[leaf_lanes[l] / W].count[leaf_lanes[l] % W];
    first[l + 1] = first[l] + TriangleBlocks::blocks_for(count);
  }
  blocks_.resize(first.back());
  parallel_for_range(
      leaf_lanes.size(),
      [&](size_t begin, size_t end) {
        for (size_t l = begin; l < end; ++l) {
          WideNode<W>& node = nodes[leaf_lanes[l] / W];
          const int lane = leaf_lanes[l] % W;
          blocks_.fill(first[l], prims, refs.subspan(node.child[lane], node.count[lane]));
          node.child[lane] = first[l];
        }
      },
      1024);
}

/// A ray's values for the box tests of an interleaved traversal, made when it starts (those of
/// traverse() are locals of its loop).
template <int W>
struct WideBoxRay {
  using F = FloatW<W>;
  F ox, oy, oz, ix, iy, iz, fx, fy, fz, t0;
  int nx, ny, nz;

  explicit WideBoxRay(const PreparedRay& pr) {
    constexpr float kFarScale = 1.0f + 2.0f * gamma(3);
    ox = F::broadcast(pr.ray.o.x), oy = F::broadcast(pr.ray.o.y), oz = F::broadcast(pr.ray.o.z);
    ix = F::broadcast(pr.inv_dir.x), iy = F::broadcast(pr.inv_dir.y);
    iz = F::broadcast(pr.inv_dir.z);
    fx = F::broadcast(pr.inv_dir.x * kFarScale), fy = F::broadcast(pr.inv_dir.y * kFarScale);
    fz = F::broadcast(pr.inv_dir.z * kFarScale);
    t0 = F::broadcast(pr.ray.tmin);
    nx = pr.neg[0], ny = 2 + pr.neg[1], nz = 4 + pr.neg[2];
  }
};

/// One ray's interleaved traversal: where it goes next (a node, count 0, or a leaf), what it
/// deferred, whether it found a hit, and the bound its boxes are culled at (query_cull of its
/// hit.t, renewed when a leaf has a hit).
template <int W, class Node>
struct WideBvh<W, Node>::Walk {
  uint32_t child = 0, count = 0;  // the root, an inner node
  int sp = 0;
  bool found = false;
  float cull = kInfinity;
  StackEntry stack[kStackSize];
};

// The step is traverse()'s loop body (distance order) with the ray's state in a Walk, and a
// prefetch of wherever the ray goes next. traverse() keeps its own loop: written as this step
// over locals, the single-ray traversal lost 4 % on incoherent rays of the million-triangle
// meshes (spheres-1m 0.95 -> 0.91, terrain 0.98 -> 0.94 x Embree), with every branch the same.
template <int W, class Node>
template <bool kAnyHit, bool kTriangles>
[[gnu::always_inline]] inline bool WideBvh<W, Node>::step(const Node* nodes,
                                                         const WideBoxRay<W>& b,
                                                         const PreparedRay& pr, Hit& hit,
                                                         Walk& w) const {
  using F = FloatW<W>;
  // Starts loading a node or leaf the ray will visit (as traverse() does).
  const auto prefetch = [&](uint32_t c, uint32_t count) {
    prefetch_child<kTriangles>(nodes, c, count);
  };
  // Where the ray goes next, loading it while the other rays take their steps.
  const auto go = [&](uint32_t c, uint32_t count) {
    w.child = c, w.count = count;
    prefetch(c, count);
    return false;
  };
  if (w.count == 0) {
    const Node& n = nodes[w.child];
    const F t1 = F::broadcast(w.cull);  // hit.h
    const F near = max((plane(n, b.nx) - b.ox) * b.ix,
                       max((plane(n, b.ny) - b.oy) * b.iy,
                           max((plane(n, b.nz) - b.oz) * b.iz, b.t0)));
    const F far = min((plane(n, b.nx ^ 1) - b.ox) * b.fx,
                      min((plane(n, b.ny ^ 1) - b.oy) * b.fy,
                          min((plane(n, b.nz ^ 1) - b.oz) * b.fz, t1)));
    unsigned mask = mask_le(near, far) & slots(n);
    if (mask != 0) {
      const auto defer = [&](int i, float t) {
        w.stack[w.sp++] = {n.child[i], n.count[i], t};
        prefetch(n.child[i], n.count[i]);
      };
      if constexpr (kAnyHit) {
        // As traverse(): one child now (any_hit_first), the other leaves before the inner
        // children.
        const unsigned leaves = mask & leaf_lanes(n);
        const int i0 = any_hit_first<W>(mask, leaves, near, far, any_hit_span_);
        mask &= ~(1u << i0);
        for (unsigned m = mask & ~leaves; m; m &= m - 1) defer(std::countr_zero(m), 0.0f);
        for (unsigned m = mask & leaves; m; m &= m - 1) defer(std::countr_zero(m), 0.0f);
        return go(n.child[i0], n.count[i0]);
      }
      alignas(4 * W) float dist[W];
      near.store(dist);
      const int i0 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) return go(n.child[i0], n.count[i0]);
      const int i1 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {  // the order of traverse(), which a key sort differs from at -0 and +0
        const int a = dist[i1] < dist[i0] ? i1 : i0, c = i0 ^ i1 ^ a;
        defer(c, dist[c]);
        return go(n.child[a], n.count[a]);
      }
      // The nearest next, the others pushed farthest first.
      uint64_t key[W];
      int k = 0;
      for (unsigned m = mask | 1u << i0 | 1u << i1; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        key[k++] = distance_key(dist[i], i);
      }
      sort_small(key, k);
      for (int j = k - 1; j > 0; --j) defer(key_lane(key[j]), dist[key_lane(key[j])]);
      const int first = key_lane(key[0]);
      return go(n.child[first], n.count[first]);
    }
  } else {
    const bool leaf_hit =
        kTriangles ? blocks_.intersect<kAnyHit>(BlockRay(pr), w.child, w.count, hit)
                   : leaf_.intersect<kAnyHit, false>(*prims_, pr, w.child, w.count, hit, NoCost{});
    if (leaf_hit) {
      w.found = true;
      if constexpr (kAnyHit) return true;
      w.cull = query_cull<kAnyHit>(hit.t);
    }
  }
  // The next deferred child that may still hold a closer hit.
  do {
    if (w.sp == 0) return true;
    --w.sp;
  } while (w.stack[w.sp].t > w.cull);
  w.child = w.stack[w.sp].child, w.count = w.stack[w.sp].count;
  if (w.count == 0) prefetch_line(nodes[w.child].child);
  return false;
}

template <int W, class Node>
template <bool kAnyHit, bool kTriangles, bool kOctant, class Cost>
bool WideBvh<W, Node>::traverse(const PreparedRay& pr, Hit& hit, Cost cost) const {
  using F = FloatW<W>;
  // Per-ray values: origin, 1/d (scaled up for exit distances, Pharr et al., "Physically Based
  // Rendering", 3rd ed., section 3.9.2) and the near-plane rows chosen by the direction signs.
  constexpr float kFarScale = 1.0f + 2.0f * gamma(3);
  const F ox = F::broadcast(pr.ray.o.x), oy = F::broadcast(pr.ray.o.y),
          oz = F::broadcast(pr.ray.o.z);
  const F ix = F::broadcast(pr.inv_dir.x), iy = F::broadcast(pr.inv_dir.y),
          iz = F::broadcast(pr.inv_dir.z);
  const F fx = F::broadcast(pr.inv_dir.x * kFarScale), fy = F::broadcast(pr.inv_dir.y * kFarScale),
          fz = F::broadcast(pr.inv_dir.z * kFarScale);
  const int nx = pr.neg[0], ny = 2 + pr.neg[1], nz = 4 + pr.neg[2];
  const F t0 = F::broadcast(pr.ray.tmin);
  // Octant order (order=octant, 8 lanes): the ray's octant, bit a set where d[a] < 0.
  constexpr bool octant = W == 8 && kOctant;
  const int oct = pr.neg[0] | pr.neg[1] << 1 | pr.neg[2] << 2;
  // The node array in a local: through `this`, register pressure made GCC reload the object
  // pointer and then the array's at every node (any-hit rays +0.01-0.03 x Embree without).
  const Node* const nodes = nodes_.data();
  // A deferred child will often be visited, and the child taken next is visited now: start
  // loading it while the nearer ones are traversed or the others deferred: all of it (a node's
  // lines, a leaf's blocks) in structures over 1 MiB. The first line alone left the rest to be
  // fetched when the box test or the leaf test asked (on a Zen 4, occlusion rays +9-28 % and
  // incoherent ones +8-17 % on cylinder_engine, spheres-1m and the terrain; docs/accel.md,
  // "2026-12-06, nineteenth session").
  const auto prefetch = [&](uint32_t c, uint32_t count) {
    prefetch_child<kTriangles>(nodes, c, count);
  };

  // The leaf test's per-ray vectors, made here where the target has 32 vector registers
  // (kBlockRayPerRay: on a Zen 4, occlusion rays +7-8 % x Embree on the bunny, human_blend and
  // cylinder_engine, incoherent ones +3-5 %, shadow rays +5-9 %; docs/accel.md, "2026-12-07,
  // twentieth session"), else at each leaf: held across the loop, they were 7 more than AVX2's
  // 16 registers could keep with the box test's 10, and were spilled at every ray's start
  // (primary rays +4-14 % x Embree, shadow rays -3 to +1 %, made at each leaf).
  const MaybeBlockRay<kTriangles && kBlockRayPerRay> block_ray(pr);
  StackEntry stack[kStackSize];
  int sp = 0;
  uint32_t child = 0, count = 0;  // the root, an inner node
  bool found = false;
  // Boxes are culled at cull_bound(hit.t) (hit.h), kept here and renewed when a leaf has a hit.
  float cull = query_cull<kAnyHit>(hit.t);
  while (true) {
    if (count == 0) {
      // Slab test of all W children at once. max(x, acc) and min(x, acc) keep acc where x is
      // NaN (0 * inf: the origin on a plane of a zero direction component), so such a term
      // never rejects a box; the running bounds start from the ray interval and each plane's
      // distance enters as the first operand.
      const Node& n = nodes[child];
      cost.node();
      // The children's indices lie on another cache line than the boxes; which one is needed
      // depends on the box test, so fetch the line now rather than after it (two misses in
      // parallel instead of one after the other).
      prefetch_line(n.child);
      const F t1 = F::broadcast(cull);
      const F near = max((plane(n, nx) - ox) * ix,
                         max((plane(n, ny) - oy) * iy, max((plane(n, nz) - oz) * iz, t0)));
      const F far = min((plane(n, nx ^ 1) - ox) * fx,
                        min((plane(n, ny ^ 1) - oy) * fy, min((plane(n, nz ^ 1) - oz) * fz, t1)));
      unsigned mask = mask_le(near, far) & slots(n);
      if (mask == 0) goto pop;
      if constexpr (kAnyHit) {
        // Any hit ends the query, so distances do not matter (hit.t never shrinks before the
        // end). Leaves first: a leaf hit ends the query with no further node fetched, so the
        // first leaf child hit is tested now and the other leaves are popped before the inner
        // children (pushed last, taken first); with no leaf hit, the inner child the ray
        // crosses longest goes first (any_hit_first).
        const unsigned leaves = mask & leaf_lanes(n);
        const int i0 = any_hit_first<W>(mask, leaves, near, far, any_hit_span_);
        // The child taken next starts loading before the others are deferred (a leaf's first
        // block is where occlusion rays wait on a Zen 4: cylinder_engine +7 %, human_blend +5 %;
        // docs/accel.md, "2026-12-06, eighteenth session").
        prefetch(n.child[i0], n.count[i0]);
        mask &= ~(1u << i0);
        const auto defer = [&](unsigned lanes) {
          for (; lanes; lanes &= lanes - 1) {
            const int i = std::countr_zero(lanes);
            stack[sp++] = {n.child[i], n.count[i], 0.0f};
            prefetch(n.child[i], n.count[i]);
          }
        };
        defer(mask & ~leaves);
        defer(mask & leaves);
        child = n.child[i0], count = n.count[i0];
        continue;
      }
      alignas(4 * W) float dist[W];
      near.store(dist);
      const int i0 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {  // one child: go there
        child = n.child[i0], count = n.count[i0];
        continue;
      }
      if constexpr (octant) {
        // The ray's octant order (slots laid out by the collapse): the first lane hit in that
        // order next, the others pushed last-first. The next node does not wait on the
        // distances, which only go with the deferred lanes for culling at the pop.
        mask |= 1u << i0;
        unsigned order = mask;
        if (oct & 1) order = ((order & 0x55u) << 1) | ((order >> 1) & 0x55u);
        if (oct & 2) order = ((order & 0x33u) << 2) | ((order >> 2) & 0x33u);
        if (oct & 4) order = ((order & 0x0fu) << 4) | ((order >> 4) & 0x0fu);
        const int first = std::countr_zero(order) ^ oct;
        for (unsigned rest = order & (order - 1); rest;) {
          const int j = 31 - std::countl_zero(rest);
          rest &= ~(1u << j);
          const int i = j ^ oct;
          stack[sp++] = {n.child[i], n.count[i], dist[i]};
          prefetch(n.child[i], n.count[i]);
        }
        child = n.child[first], count = n.count[first];
        continue;
      }
      const int i1 = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {  // two: the nearer now, the other later
        // Which is nearer is a coin toss for incoherent rays, yet GCC's compare and branch here
        // beats a select (forced by integer masks: primary rays -10 %, bounce -4 %): the
        // predicted branch lets the next node's load start before the distances are compared.
        const bool swap = __builtin_expect_with_probability(dist[i1] < dist[i0], 1, 0.5);
        const int a = swap ? i1 : i0, b = i0 ^ i1 ^ a;
        stack[sp++] = {n.child[b], n.count[b], dist[b]};
        prefetch(n.child[b], n.count[b]);
        child = n.child[a], count = n.count[a];
        continue;
      }
      // Three or more: sort (distance, lane) keys (three or four by networks of selects, not
      // branches: small_sort.h), push all but the nearest farthest first, take the nearest.
      uint64_t key[W];
      int k = 0;
      for (unsigned m = mask | 1u << i0 | 1u << i1; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        key[k++] = distance_key(dist[i], i);
      }
      sort_small(key, k);
      for (int j = k - 1; j > 0; --j) {
        const int i = key_lane(key[j]);
        stack[sp++] = {n.child[i], n.count[i], dist[i]};
        prefetch(n.child[i], n.count[i]);
      }
      const int first = key_lane(key[0]);
      child = n.child[first], count = n.count[first];
      continue;
    }
    // Leaf: test its primitives; each hit shrinks hit.t.
    bool leaf_hit;
    cost.node();
    if constexpr (kTriangles) {
      if constexpr (kBlockRayPerRay)
        leaf_hit = blocks_.intersect<kAnyHit>(block_ray, child, count, hit, cost);
      else
        leaf_hit = blocks_.intersect<kAnyHit>(BlockRay(pr), child, count, hit, cost);
    } else {
      leaf_hit = leaf_.intersect<kAnyHit, false>(*prims_, pr, child, count, hit, cost);
    }
    if (leaf_hit) {
      if constexpr (kAnyHit) return true;
      found = true;
      cull = query_cull<kAnyHit>(hit.t);
    }
  pop:
    // The next deferred child that may still hold a closer hit.
    do {
      if (sp == 0) return found;
      --sp;
    } while (stack[sp].t > cull);
    child = stack[sp].child, count = stack[sp].count;
  }
}

template <int W, class Node>
template <bool kAnyHit, bool kTriangles>
void WideBvh<W, Node>::interleave(std::span<const Ray> rays, std::span<Hit> hits,
                                  std::span<uint8_t> blocked) const {
  // Up to kInterleave rays in flight, each a node or leaf per turn, round robin; a finished
  // ray's slot takes the next ray of the batch. Each step prefetches where its ray goes next,
  // so the other rays' steps run while those lines arrive (a single ray waits for them).
  const Node* const nodes = nodes_.data();
  struct Slot {
    PreparedRay pr{Ray{}};
    WideBoxRay<W> box{pr};
    size_t index = 0;
  };
  Walk walks[kInterleave];
  Slot slot[kInterleave];
  int live = 0;
  size_t next = 0;
  // Starts slot `k` on the next traceable ray of the batch; false when none is left.
  const auto start = [&](int k) {
    while (next < rays.size()) {
      const size_t i = next++;
      Hit& h = hits[i];
      h = Hit{};
      h.t = rays[i].tmax;
      if constexpr (kAnyHit) blocked[i] = 0;
      if (!traceable(rays[i])) continue;
      slot[k].pr = prepare_slot_ray(rays[i]);
      slot[k].box = WideBoxRay<W>(slot[k].pr);
      slot[k].index = i;
      walks[k].child = 0, walks[k].count = 0, walks[k].sp = 0, walks[k].found = false;
      walks[k].cull = query_cull<kAnyHit>(h.t);
      prefetch_line(nodes[0].child);
      return true;
    }
    return false;
  };
  while (live < kInterleave && start(live)) ++live;
  while (live > 0) {
    for (int k = 0; k < live;) {
      Walk& w = walks[k];
      const size_t i = slot[k].index;
      if (!step<kAnyHit, kTriangles>(nodes, slot[k].box, slot[k].pr, hits[i], w)) {
        ++k;
        continue;
      }
      if constexpr (kAnyHit) blocked[i] = w.found;
      if (start(k)) continue;
      // No ray left to start: the last slot's ray moves here.
      --live;
      if (k < live) {
        const Walk& last = walks[live];
        w.child = last.child, w.count = last.count, w.sp = last.sp, w.found = last.found;
        w.cull = last.cull;
        std::copy(last.stack, last.stack + last.sp, w.stack);
        slot[k] = slot[live];
      }
    }
  }
}

template <int W, class Node>
template <bool kAnyHit>
void WideBvh<W, Node>::batch(std::span<const Ray> rays, std::span<Hit> hits,
                             std::span<uint8_t> blocked, BatchOrder order) const {
  // Coherent rays go one at a time: interleaved, neighbours that would find the same nodes in
  // the caches and the same branches predicted scramble both (terrain, primary rays 1.04 ->
  // 0.80 x Embree).
  // The octant order (order=octant) is not interleaved: its closest-hit rays go one at a time.
  const bool interleaved = interleave_ && order == BatchOrder::kIncoherent && !nodes_.empty() &&
                           (kAnyHit || !octant_order_);
  if (interleaved)
    return blocks_.size() ? interleave<kAnyHit, true>(rays, hits, blocked)
                          : interleave<kAnyHit, false>(rays, hits, blocked);
  for (size_t i = 0; i < rays.size(); ++i) {
    if constexpr (kAnyHit)
      blocked[i] = occluded(rays[i]);
    else
      intersect(rays[i], hits[i]);
  }
}

template <int W, class Node>
void WideBvh<W, Node>::intersect_batch(std::span<const Ray> rays, std::span<Hit> hits,
                                       BatchOrder order) const {
  batch<false>(rays, hits, {}, order);
}

template <int W, class Node>
void WideBvh<W, Node>::occluded_batch(std::span<const Ray> rays, std::span<uint8_t> out,
                                      BatchOrder order) const {
  // Any-hit traversal needs a running hit record per ray: kept in a small buffer, a chunk of
  // rays at a time.
  constexpr size_t kChunk = 256;
  Hit scratch[kChunk];
  for (size_t begin = 0; begin < rays.size(); begin += kChunk) {
    const size_t n = std::min(kChunk, rays.size() - begin);
    batch<true>(rays.subspan(begin, n), std::span<Hit>(scratch, n), out.subspan(begin, n), order);
  }
}

template <int W, class Node>
template <class Cost>
bool WideBvh<W, Node>::closest(const PreparedRay& pr, Hit& hit, Cost cost) const {
  if (octant_order_)
    return blocks_.size() ? traverse<false, true, true>(pr, hit, cost)
                          : traverse<false, false, true>(pr, hit, cost);
  return blocks_.size() ? traverse<false, true>(pr, hit, cost)
                        : traverse<false, false>(pr, hit, cost);
}

template <int W, class Node>
bool WideBvh<W, Node>::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  return closest(pr, hit);
}

template <int W, class Node>
bool WideBvh<W, Node>::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || nodes_.empty()) return false;
  const PreparedRay pr(ray);
  return closest(pr, hit, CostCounter{&cost});
}

template <int W, class Node>
bool WideBvh<W, Node>::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  if (!traceable(ray) || nodes_.empty()) return false;
  const PreparedRay pr(ray);
  Hit hit;
  hit.t = ray.tmax;
  const CostCounter c{&cost};
  return blocks_.size() ? traverse<true, true>(pr, hit, c) : traverse<true, false>(pr, hit, c);
}

template <int W, class Node>
bool WideBvh<W, Node>::occluded(const Ray& ray) const {
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  Hit hit;
  hit.t = ray.tmax;
  return blocks_.size() ? traverse<true, true>(pr, hit) : traverse<true, false>(pr, hit);
}

template class WideBvh<4>;
template class WideBvh<8>;
template class WideBvh<8, CompressedNode>;
template class WideBvh<16>;

}  // namespace penumbra
