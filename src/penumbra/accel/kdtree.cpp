#include "penumbra/accel/kdtree.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "penumbra/accel/build/kd_clip.h"
#include "penumbra/accel/build/kd_sah_builder.h"
#include "penumbra/accel/build/kd_simple_builder.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"
#include "penumbra/geometry/float_error.h"

namespace penumbra {
namespace {

/// Relative widening of the cell intervals the traversal derives: a plane distance
/// (split - o) * (1 / d) in float is within gamma(3) of the exact one, and comparing two such
/// distances needs twice that. With intervals widened by this much, a ray that grazes a cell
/// edge or corner visits the cells on both sides of it instead of possibly neither; the extra
/// cells are those within a few ulps of a plane crossing, so the cost does not show.
constexpr float kSlack = 4.0f * gamma(3);

/// max(a, b), or b when a is NaN.
inline float max_keep(float a, float b) {
  return a > b ? a : b;
}
/// min(a, b), or b when a is NaN.
inline float min_keep(float a, float b) {
  return a < b ? a : b;
}

/// An integer whose signed order is the order of the floats (-0 below +0; no NaN).
inline int32_t order_key(float f) {
  const auto w = std::bit_cast<uint32_t>(f);
  return int32_t(w ^ (uint32_t(int32_t(w) >> 31) & 0x7fffffffu));
}

/// k[axis] for axis 0..2 without a load or a branch: two conditional moves after the axis is
/// known, where a load from the array would take five cycles and a branch would mispredict.
inline int32_t select3(int axis, const int32_t (&k)[3]) {
#if defined(__x86_64__)
  int32_t v = k[0];
  asm("test $1, %[ax]\n\tcmovnz %[k1], %[v]\n\ttest $2, %[ax]\n\tcmovnz %[k2], %[v]"
      : [v] "+r"(v)
      : [ax] "r"(axis), [k1] "r"(k[1]), [k2] "r"(k[2])
      : "cc");
  return v;
#else
  return k[axis];
#endif
}

/// Swaps a and b when bit `axis_word mod 32` of `repeated` is set: with a per-axis bit set whose
/// nibble is repeated over the 32 bits (0x11111111 * set), that is the set's bit for the axis in
/// the word's low two bits (KdNode::axis_word), whatever the word's bits 2-4 are. A bit test and
/// two conditional moves, two cycles after the word is loaded, where GCC made a select of two
/// indices a branch, and an array indexed by the axis costs a load.
inline void swap_by_axis(uint32_t repeated, uint32_t axis_word, uint32_t& a, uint32_t& b) {
#if defined(__x86_64__)
  const uint32_t a0 = a;
  asm("bt %[w], %[rep]\n\tcmovc %[b], %[a]\n\tcmovc %[a0], %[b]"
      : [a] "+&r"(a), [b] "+&r"(b)
      : [w] "r"(axis_word), [rep] "r"(repeated), [a0] "r"(a0)
      : "cc");
#else
  if ((repeated >> (axis_word & 31u)) & 1u) std::swap(a, b);
#endif
}

/// A deferred far child and its interval along the ray.
struct StackEntry {
  uint32_t node;
  float tmin, tmax;
};

}  // namespace

KdTree::KdTree(const ParamList& params) {
  std::string criterion = "sah";
  int given = 0;
  for (const char* c : {"sah", "median", "gap"}) {
    if (!params.has(c)) continue;
    if (!params.get_flag(c)) throw Error(fmt::format("kdtree: criterion '{}' cannot be false", c));
    criterion = c, ++given;
  }
  if (given > 1) throw Error("kdtree: give at most one criterion of sah, median, gap");
  params_.criterion = criterion == "sah"      ? KdCriterion::kSah
                      : criterion == "median" ? KdCriterion::kMedian
                                              : KdCriterion::kGap;
  const KdBuildParams defaults;
  params_.traversal_cost = float(params.get_real("ct", defaults.traversal_cost, 0.0, 1000.0));
  params_.intersect_cost = float(params.get_real("ci", defaults.intersect_cost, 0.01, 1000.0));
  params_.empty_bonus = float(params.get_real("empty_bonus", defaults.empty_bonus, 0.0, 0.99));
  params_.max_leaf =
      int(params.get_int("leaf", params_.criterion == KdCriterion::kSah ? 0 : 8, 0, 1024));
  params_.max_depth = int(params.get_int("depth", 0, 1, kKdMaxDepth));
  params_.clip = !params.has("clip") || params.get_flag("clip");
  params.check_all_used();
  name_ = "kdtree:" + criterion;
  for (const char* key : {"ct", "ci", "empty_bonus", "leaf", "depth", "clip", "isa"})
    if (params.has(key)) name_ += fmt::format(",{}={}", key, params.get_string(key, ""));
}

void KdTree::build(const PrimitiveSet& prims) {
  const Timer timer;
  prims_ = &prims;
  nodes_ = {}, refs_ = {}, blocks_ = {};  // releasing the memory of a previous build
  bounds_ = {};
  max_extent_ = 0;
  stats_ = {};
  // One reference per primitive with finite bounds that a ray can hit (never_hit); zeros as +0
  // so that boxes compare alike.
  std::vector<KdPrim> refs;
  refs.reserve(prims.size());
  for (uint32_t id = 0; id < prims.size(); ++id) {
    Bounds3 b = prims.prim_bounds(id);
    if (b.empty() || never_hit(prims, id)) continue;
    b.lo = b.lo + Vec3(0.0f), b.hi = b.hi + Vec3(0.0f);
    bounds_.extend(b);
    max_extent_ = std::max(max_extent_, max_component(b.hi - b.lo));
    refs.push_back({b, id});
  }
  const size_t n = refs.size();
  // Triangle leaves are tested four at a time (TriangleBlocks): let the SAH count blocks.
  KdBuildParams sah_params = params_;
  if (prims.all_triangles()) sah_params.block_shift = 2;
  if (n > 0) {
    KdSubtree tree = params_.criterion == KdCriterion::kSah
                         ? build_kd_sah(prims, std::move(refs), bounds_, sah_params)
                         : build_kd_simple(prims, std::move(refs), bounds_, params_);
    nodes_.assign(tree.nodes.begin(), tree.nodes.end());
    stats_.leaves = tree.leaves;
    stats_.max_depth = tree.max_depth;
    stats_.prim_refs = tree.refs.size();
    stats_.extra = {{"empty leaves", double(tree.empty_leaves)},
                    {"refs/prim", double(tree.refs.size()) / double(n)},
                    {"depth limit", double(kd_depth_limit(params_, n))}};
    if (prims.all_triangles()) {
      // Each leaf's references from a multiple of four, for the blocks.
      size_t padded = 0;
      for (const KdNode& node : nodes_) padded += node.is_leaf() ? (node.count() + 3) / 4 * 4 : 0;
      if (padded > kKdMaxIndex) throw Error("kdtree: more than 2^30 padded references");
      refs_.reserve(padded);
      for (KdNode& node : nodes_) {
        if (!node.is_leaf()) continue;
        const auto first = uint32_t(refs_.size());
        refs_.insert(refs_.end(), tree.refs.begin() + node.first(),
                     tree.refs.begin() + node.first() + node.count());
        refs_.resize((refs_.size() + 3) / 4 * 4, kNoPrim);
        node = KdNode::leaf(first, node.count());
      }
      // Each leaf's blocks from its first reference on (a leaf is one unit: its blocks pair up).
      std::vector<KdNode> leaves;
      std::vector<Bounds3> cells(nodes_.size()), leaf_cells;
      cells[0] = bounds_;
      for (size_t i = 0; i < nodes_.size(); ++i) {
        const KdNode node = nodes_[i];
        if (node.is_leaf()) {
          if (node.count() > 0) leaves.push_back(node), leaf_cells.push_back(cells[i]);
          continue;
        }
        cells[i + 1] = cells[node.above()] = cells[i];
        cells[i + 1].hi[node.axis()] = node.split();
        cells[node.above()].lo[node.axis()] = node.split();
      }
      blocks_.resize(refs_.size() / TriangleBlocks::kLanes);
      parallel_for_range(
          leaves.size(),
          [&](size_t begin, size_t end) {
            std::vector<std::pair<double, uint32_t>> order;
            for (size_t l = begin; l < end; ++l) {
              // The leaf's triangles by their area inside the cell, largest first (then by id):
              // the likelier to be hit by a ray crossing the cell, so an any-hit test stops
              // sooner. A closest hit is the least (t, id) whatever the order.
              order.clear();
              uint32_t* r = refs_.data() + leaves[l].first();
              for (uint32_t k = 0; k < leaves[l].count(); ++k)
                order.emplace_back(-clip_prim_area(prims, r[k], leaf_cells[l]), r[k]);
              std::sort(order.begin(), order.end());
              for (uint32_t k = 0; k < leaves[l].count(); ++k) r[k] = order[k].second;
              blocks_.fill(
                  leaves[l].first() / TriangleBlocks::kLanes, prims,
                  std::span<const uint32_t>(refs_.data() + leaves[l].first(), leaves[l].count()));
            }
          },
          1024);
    } else {
      refs_.assign(tree.refs.begin(), tree.refs.end());
    }
  }
  // Mark the children that are empty leaves, so that the traversal never loads them, and leave
  // those leaves out of the array (22 % of the nodes on spheres-1m): a node whose below child is
  // left out has its above child next. When both children are empty the below one stays, never
  // loaded, so that every index stored (and prefetched) stays inside the array.
  if (nodes_.size() > 1 && nodes_.size() < (size_t(1) << 28)) {
    const auto empty = [&](size_t c) { return nodes_[c].is_leaf() && nodes_[c].count() == 0; };
    std::vector<bool> drop(nodes_.size(), false);
    for (size_t i = 0; i < nodes_.size(); ++i) {
      const KdNode n = nodes_[i];
      if (n.is_leaf()) continue;
      drop[n.above()] = empty(n.above());
      drop[i + 1] = empty(i + 1) && !drop[n.above()];
    }
    std::vector<uint32_t> pos(nodes_.size());
    uint32_t kept = 0;
    for (size_t i = 0; i < nodes_.size(); ++i) pos[i] = kept, kept += !drop[i];
    std::vector<KdNode, ArrayAllocator<KdNode>> packed;
    packed.reserve(kept);
    for (size_t i = 0; i < nodes_.size(); ++i) {
      const KdNode n = nodes_[i];
      if (drop[i]) continue;
      if (n.is_leaf()) {
        packed.push_back(n);
        continue;
      }
      // A left-out above child is never loaded, but its index is prefetched: the below child's.
      const uint32_t mask = uint32_t(empty(i + 1)) | uint32_t(empty(n.above())) << 1;
      const uint32_t above = drop[n.above()] ? pos[i] + 1 : pos[n.above()];
      packed.push_back(KdNode::inner(n.axis(), n.split(), above).with_empty_children(mask));
    }
    nodes_ = std::move(packed);
  }
  for (int a = 0; a < 3; ++a) planes_[0][a] = bounds_.lo[a], planes_[1][a] = bounds_.hi[a];
  stats_.nodes = stats_.leaves == 0 ? 0 : 2 * stats_.leaves - 1;  // of the tree, stored or not
  stats_.extra.emplace_back("stored nodes", double(nodes_.size()));
  stats_.bytes =
      nodes_.capacity() * sizeof(KdNode) + refs_.capacity() * sizeof(uint32_t) + blocks_.bytes();
  stats_.build_ms = timer.elapsed_ms();
}

template <bool kAnyHit, bool kTriangles, class Cost>
bool KdTree::traverse(const PreparedRay& pr, Hit& hit, Cost cost) const {
  // Per-ray values in arrays: Vec3's operator[] is a chain of selects, too slow per node.
  const float o[3] = {pr.ray.o.x, pr.ray.o.y, pr.ray.o.z};
  const float inv[3] = {pr.inv_dir.x, pr.inv_dir.y, pr.inv_dir.z};
  // Cells are dropped beyond cull_bound(hit.t, size_slack), not hit.t (hit.h): a triangle's t
  // may lie below the entry of a cell that holds it by a share of its size. Renewed at each hit.
  const float size_slack = cull_slack(max_extent_, inv);
  float cull = query_cull<kAnyHit>(hit.t, size_slack);
  const uint32_t neg_mask[3] = {0u - uint32_t(pr.neg[0]), 0u - uint32_t(pr.neg[1]),
                                0u - uint32_t(pr.neg[2])};
  const uint32_t neg_rep =
      0x11111111u * uint32_t(pr.neg[0] | pr.neg[1] << 1 | pr.neg[2] << 2);
  // The ray's interval inside the root cell (slab test; a NaN from a ray lying in a face plane
  // keeps the running bound), widened like every other cell interval.
  float tmin = pr.ray.tmin, tmax = hit.t;
  for (int a = 0; a < 3; ++a) {
    const float tn = (planes_[pr.neg[a]][a] - o[a]) * inv[a];
    const float tf = (planes_[pr.neg[a] ^ 1][a] - o[a]) * inv[a];
    tmin = tn > tmin ? tn : tmin;
    tmax = tf < tmax ? tf : tmax;
  }
  if (!(tmin <= tmax)) return false;
  tmin -= kSlack * std::fabs(tmin);
  tmax += kSlack * std::fabs(tmax);

  const KdNode* nodes = nodes_.data();
  const MaybeBlockRay<kTriangles> block_ray(pr);
  StackEntry stack[kKdMaxDepth];
  int sp = 0;
  uint32_t index = 0;
  bool found = false;
  KdNode n = nodes[0];
  const bool inside = bounds_.contains(pr.ray.o);
  if (inside) {
    // A ray that starts inside the tree (every ray from a surface, and the random rays) first
    // descends to the leaf that holds its origin. The child to enter is the one on the origin's
    // side of the plane; the other one, when the ray runs towards the plane and reaches it
    // before tmax, is deferred with its part of the interval. The step has no branch but the
    // loop's: which way such a descent turns is random for random rays, and a mispredicted step
    // costs as long as the chain that decides it. The side is an integer comparison and the
    // child a conditional move, so the next node's address is known about ten cycles after the
    // node's load, where a plane distance takes twice that (docs/accel/kdtree.md, "The first
    // descent"). The child on the origin's side may get an empty interval (an origin within
    // tmin of a plane), which wastes the visit and loses nothing.
    //
    // Off the plane, the side is exact. For an origin in the plane any side is correct (the
    // other is then deferred with the whole interval), and the side the ray goes to saves a
    // visit: so the origin's keys are one less for a negative direction, which makes such an
    // origin count as below the plane (the key of a finite float is at least INT32_MIN + 2^23:
    // this does not wrap), and zeros are +0, as the splits (KdNode::inner).
    const int32_t o_keys[3] = {order_key(o[0] + 0.0f) - pr.neg[0],
                               order_key(o[1] + 0.0f) - pr.neg[1],
                               order_key(o[2] + 0.0f) - pr.neg[2]};
    while (!n.is_leaf()) {
      cost.node();
      const int axis = n.axis();
      const float split = n.split();
      const uint32_t below = index + 1, above = n.above();
      const bool up = select3(axis, o_keys) >= order_key(split);
      const uint32_t near = up ? above : below, far = up ? below : above;
      const uint32_t empty = n.empty_children();
      const uint32_t near_empty = (empty >> uint32_t(up)) & 1u;
      const uint32_t far_empty = (empty >> uint32_t(!up)) & 1u;
      // The plane lies ahead when the ray runs from the origin's side towards it (decided by
      // the signs, not by tp, which can round to 0), and for a ray lying in the plane (d = 0
      // there, tp NaN), which visits both sides with the whole interval. The far child is
      // deferred when the plane lies ahead before tmax (tp = +inf for a ray parallel to it).
      // The entry is written every step and kept only then.
      const float tp = (split - o[axis]) * inv[axis];
      const float slack = kSlack * std::fabs(tp);
      const bool ahead = (uint32_t(up) == (neg_mask[axis] & 1u)) | (tp != tp);
      const float far_tmin = max_keep(tp - slack, tmin);
      stack[sp] = {far, far_tmin, tmax};
      sp += int(ahead & !(tp >= tmax) & !(far_tmin > tmax) & (far_empty == 0));
      // tmax = ahead ? min_keep(tp + slack, tmax) : tmax, as a select on the bits: a
      // conditional on floats compiles to a branch.
      const uint32_t keep = 0u - uint32_t(!ahead);
      const uint32_t cut = std::bit_cast<uint32_t>(min_keep(tp + slack, tmax));
      tmax = std::bit_cast<float>((cut & ~keep) | (std::bit_cast<uint32_t>(tmax) & keep));
      if (near_empty) goto pop;
      index = near;
      n = nodes[index];
    }
    goto leaf;
  }
  while (true) {
    // Inner nodes: the child the ray enters first is the one below the plane when the direction
    // is positive on the axis. Visit the far child too only when the plane lies inside
    // (tmin, tmax); a ray lying in the plane (0 * inf = NaN) visits both with the whole interval.
    n = nodes[index];
    while (!n.is_leaf()) {
      cost.node();
      const int axis = n.axis();
      const float tp = (n.split() - o[axis]) * inv[axis];
      const uint32_t below = index + 1, above = n.above();
      // The next node is often the above child, far away in the array (the below one is the
      // next node, most often in the line already loaded): start loading it while deciding.
      // Loading the below child as well to prefetch the grandchildren (+6 % on spheres-1m's
      // incoherent rays on an Intel machine) cost more than it hid on the Zen 2 (primary rays
      // 5-8 % slower on every mesh, incoherent ones equal; docs/accel.md, "Current figures
      // (2026-12-05, second session)").
      __builtin_prefetch(&nodes[above]);
      // The child the ray meets first. A predicted step's next address waits on it alone, so
      // closest-hit rays take the direction's sign for the axis by a bit test on the node's
      // word (swap_by_axis) instead of a load indexed by the axis: camera rays 7-12 % faster
      // on the five meshes, the others within +-2 %. Any-hit rays kept the load, which was 2 %
      // faster for them (docs/accel.md, "2026-12-07, twenty-seventh session").
      uint32_t first = below, second = above;
      if constexpr (kAnyHit) {
        first = below ^ ((below ^ above) & neg_mask[axis]);
        second = below ^ above ^ first;
      } else {
        swap_by_axis(neg_rep, n.axis_word(), first, second);
      }
      // Children that are empty leaves are skipped without being loaded.
      const uint32_t first_is_above = neg_mask[axis] & 1u, empty = n.empty_children();
      const bool first_empty = (empty >> first_is_above) & 1u;
      const bool second_empty = (empty >> (first_is_above ^ 1u)) & 1u;
      if (tp >= tmax) {
        if (first_empty) goto pop;
        index = first;
      } else if (tp <= tmin) {
        if (second_empty) goto pop;
        index = second;
      } else if (!kAnyHit && inside) {
        // Both sides, for a closest-hit ray from inside the tree (random rays, bounces). Which
        // of the children are empty leaves decides the next node, the interval and whether the
        // far one is deferred, by selects, not branches, which such rays mispredict: incoherent
        // rays +1-4 %, bounces +3-6 %. Camera rays, whose steps are predicted, keep the branches
        // (the selects cost them 6-10 %; docs/accel.md, "2026-12-07, twenty-seventh session").
        if (first_empty & second_empty) goto pop;
        const float slack = kSlack * std::fabs(tp);
        const float far_tmin = max_keep(tp - slack, tmin), near_tmax = min_keep(tp + slack, tmax);
        stack[sp] = {second, far_tmin, tmax};
        sp += int(!first_empty & !second_empty);
        const uint32_t go_far = 0u - uint32_t(first_empty);
        index = first ^ ((first ^ second) & go_far);
        tmin = std::bit_cast<float>((std::bit_cast<uint32_t>(far_tmin) & go_far) |
                                    (std::bit_cast<uint32_t>(tmin) & ~go_far));
        tmax = std::bit_cast<float>((std::bit_cast<uint32_t>(tmax) & go_far) |
                                    (std::bit_cast<uint32_t>(near_tmax) & ~go_far));
        if (tmin > cull) goto pop;  // as a deferred cell would be dropped
      } else {
        const float slack = kSlack * std::fabs(tp);
        if (first_empty) {
          if (second_empty) goto pop;
          tmin = max_keep(tp - slack, tmin);
          if (tmin > cull) goto pop;  // as a deferred cell would be dropped
          index = second;
        } else {
          if constexpr (kAnyHit) {
            // Any hit ends the query, in whatever order the cells are tried: a far child that
            // is a leaf is tested before the near one's subtree is descended, as the BVH tests
            // leaves first (occlusion rays +2-9 % x Embree, shadow rays +1-3 %), and between two
            // of a kind the one with the longer part of the interval goes first, the likelier
            // to hold a surface the ray hits (occlusion +5-17 %, shadow -3 to +8 %; as the
            // BVH's anyhit=span; docs/accel.md, "2026-12-05, tenth session"). A NaN plane
            // distance (a ray in the plane) keeps the near child first.
            const auto far_first = [&] {
              const bool far_leaf = nodes[second].is_leaf(), near_leaf = nodes[first].is_leaf();
              return far_leaf != near_leaf ? far_leaf : tmax - tp > tp - tmin;
            };
            if (!second_empty && far_first()) {
              stack[sp++] = {first, tmin, min_keep(tp + slack, tmax)};
              tmin = max_keep(tp - slack, tmin);
              index = second;
              n = nodes[index];
              continue;
            }
          }
          if (!second_empty) stack[sp++] = {second, max_keep(tp - slack, tmin), tmax};
          tmax = min_keep(tp + slack, tmax);
          index = first;
        }
      }
      n = nodes[index];
    }
    // Leaf: test its primitives; each hit shrinks hit.t.
  leaf:
    cost.node();
    if constexpr (kTriangles) {
      // Blocks of four, tested four at a time (bit for bit the scalar test, by (t, id)).
      // All the leaf's blocks start loading before the first is tested (a Zen 4: occlusion and
      // shadow rays +3-7 %, closest hits -5 to +9 %; docs/accel.md, "2026-12-06, nineteenth
      // session").
      blocks_.prefetch(n.first() / 4, n.count());
      if (blocks_.intersect<kAnyHit>(block_ray, n.first() / 4, n.count(), hit, cost)) {
        if constexpr (kAnyHit) return true;
        found = true;
        cull = cull_bound(hit.t, size_slack);
      }
    } else {
      for (uint32_t i = n.first(), end = n.first() + n.count(); i < end; ++i) {
        cost.prims(1);
        if (prims_->intersect(refs_[i], pr, hit)) {
          if constexpr (kAnyHit) return true;
          found = true;
          cull = cull_bound(hit.t, size_slack);
        }
      }
    }
    // The next deferred cell that may still hold a closer hit (or one at the same t with a lower
    // id: hit.h), one starting at or before cull_bound(hit.t). This is the early exit: a hit well
    // inside this leaf's interval skips every deferred cell, as they start near or after its tmax,
    // except the cells beside a plane the ray lies in, which share this leaf's interval.
  pop:
    do {
      if (sp == 0) return found;
      --sp;
    } while (stack[sp].tmin > cull);
    index = stack[sp].node, tmin = stack[sp].tmin, tmax = stack[sp].tmax;
  }
}

bool KdTree::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  return blocks_.size() == 0 ? traverse<false, false>(pr, hit) : traverse<false, true>(pr, hit);
}

bool KdTree::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || nodes_.empty()) return false;
  const PreparedRay pr(ray);
  const CostCounter c{&cost};
  return blocks_.size() == 0 ? traverse<false, false>(pr, hit, c)
                             : traverse<false, true>(pr, hit, c);
}

bool KdTree::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  if (!traceable(ray) || nodes_.empty()) return false;
  const PreparedRay pr(ray);
  Hit hit;
  hit.t = ray.tmax;
  const CostCounter c{&cost};
  return blocks_.size() == 0 ? traverse<true, false>(pr, hit, c) : traverse<true, true>(pr, hit, c);
}

bool KdTree::occluded(const Ray& ray) const {
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  Hit hit;
  hit.t = ray.tmax;
  return blocks_.size() == 0 ? traverse<true, false>(pr, hit) : traverse<true, true>(pr, hit);
}

}  // namespace penumbra
