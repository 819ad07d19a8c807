#include "penumbra/accel/build/kd_sah_builder.h"

#include <algorithm>
#include <limits>

#include <fmt/format.h>
#include <oneapi/tbb/parallel_sort.h>

#include "penumbra/accel/build/bvh_split.h"
#include "penumbra/accel/build/kd_build.h"
#include "penumbra/accel/build/kd_clip.h"
#include "penumbra/accel/build/kd_events.h"
#include "penumbra/core/error.h"

namespace penumbra {

namespace {

/// A node under construction: its cell, its references (boxes clipped to the cell) and their
/// events, sorted, indexing `prims`.
struct SahNode {
  Bounds3 voxel;
  std::vector<KdPrim> prims;
  std::vector<KdEvent> events;
};

/// The best plane of a sweep.
struct SahSplit {
  float cost = std::numeric_limits<float>::infinity();
  int axis = -1;
  float pos = 0.0f;
  bool planar_below = true;  ///< primitives lying in the plane go below (else above)
};

/// Number of events of a box: two per axis, one where it is flat.
size_t event_count(const Bounds3& b) {
  return size_t(6) - (b.lo.x == b.hi.x) - (b.lo.y == b.hi.y) - (b.lo.z == b.hi.z);
}

class SahSplitter {
 public:
  SahSplitter(const PrimitiveSet& set, const KdBuildParams& params, int max_depth)
      : set_(set), p_(params), max_depth_(max_depth) {}

  /// Chooses the plane of `node` and fills its children, or returns no plane for a leaf.
  KdPlane operator()(SahNode& node, int depth, SahNode& below, SahNode& above) const {
    const size_t n = node.prims.size();
    if (n <= size_t(p_.max_leaf) || depth >= max_depth_) return {};
    const SahSplit s = sweep(node);
    // Terminate when no split is cheaper than intersecting every primitive here.
    if (s.axis < 0 || !(s.cost < p_.intersect_cost * sah_tests(uint32_t(n), p_.block_shift)))
      return {};
    distribute(node, s, below, above);
    return {s.axis, s.pos};
  }

 private:
  /// SAH cost of a split with probabilities (pl, pr) and counts (nl, nr): Wald and Havran's
  /// lambda(p) (ct + ci (pl nl + pr nr)), lambda = 1 - empty_bonus when a side is empty.
  float cost(float pl, float pr, uint32_t nl, uint32_t nr) const {
    const float c = p_.traversal_cost + p_.intersect_cost * (pl * sah_tests(nl, p_.block_shift) +
                                                             pr * sah_tests(nr, p_.block_shift));
    return (nl == 0 || nr == 0) ? c * (1.0f - p_.empty_bonus) : c;
  }

  /// Sweeps the sorted events once (all three axes), evaluating every plane strictly inside the
  /// cell with counts (below, planar, above) kept per axis (Wald and Havran's sweep).
  SahSplit sweep(const SahNode& node) const {
    SahSplit best;
    const Bounds3& v = node.voxel;
    const Vec3 d = v.diagonal();
    const float half_area = d.x * d.y + d.y * d.z + d.z * d.x;
    if (!(half_area > 0.0f)) return best;
    const float inv_area = 1.0f / half_area;
    const auto n = uint32_t(node.prims.size());
    uint32_t nl[3] = {0, 0, 0}, nr[3] = {n, n, n};
    const KdEvent* e = node.events.data();
    const size_t m = node.events.size();
    for (size_t i = 0; i < m;) {
      const uint64_t plane = kd_event_plane(e[i]);
      uint32_t ends = 0, planars = 0, starts = 0;
      while (i < m && kd_event_plane_type(e[i]) == ((plane << 2) | kKdEnd)) ++ends, ++i;
      while (i < m && kd_event_plane_type(e[i]) == ((plane << 2) | kKdPlanar)) ++planars, ++i;
      while (i < m && kd_event_plane_type(e[i]) == ((plane << 2) | kKdStart)) ++starts, ++i;
      const int k = int(plane >> 32);
      const float p = kd_key_float(uint32_t(plane));
      nr[k] -= planars + ends;
      if (p > v.lo[k] && p < v.hi[k]) {
        const int a = k == 2 ? 0 : k + 1, b = a == 2 ? 0 : a + 1;
        const float cap = d[a] * d[b], rim = d[a] + d[b];
        const float pl = (cap + (p - v.lo[k]) * rim) * inv_area;
        const float pr = (cap + (v.hi[k] - p) * rim) * inv_area;
        // Primitives lying in the plane go to the cheaper side (p_side).
        const float below_cost = cost(pl, pr, nl[k] + planars, nr[k]);
        const float above_cost = cost(pl, pr, nl[k], nr[k] + planars);
        const float c = std::min(below_cost, above_cost);
        if (c < best.cost) best = {c, k, p, below_cost <= above_cost};
      }
      nl[k] += starts + planars;
    }
    return best;
  }

  /// Classifies the references of `node` against plane `s`, clips the straddling ones, and makes
  /// the children's sorted event lists; empties `node`.
  void distribute(SahNode& node, const SahSplit& s, SahNode& below, SahNode& above) const {
    const int k = s.axis;
    const float p = s.pos;
    below.voxel = above.voxel = node.voxel;
    below.voxel.hi[k] = above.voxel.lo[k] = p;
    // Each reference: kept below or above with its box (0, 1), or clipped (2).
    const size_t n = node.prims.size();
    std::vector<uint8_t> side(n);
    std::vector<uint32_t> remap(n);
    std::vector<uint32_t> fresh_below, fresh_above;  // clipped references, as child indices
    size_t kept_events[2] = {0, 0};
    for (size_t i = 0; i < n; ++i) {
      const KdPrim& q = node.prims[i];
      const KdSide where = classify_box(q.box, k, p, s.planar_below);
      if (where != KdSide::kBoth) {
        const int c = where == KdSide::kBelow ? 0 : 1;
        SahNode& child = c == 0 ? below : above;
        side[i] = uint8_t(c);
        remap[i] = uint32_t(child.prims.size());
        child.prims.push_back(q);
        kept_events[c] += event_count(q.box);
        continue;
      }
      side[i] = 2;
      Bounds3 lb, rb;
      split_prim_bounds(set_, q.id, q.box, k, p, p_.clip, lb, rb);
      if (!lb.empty()) {
        fresh_below.push_back(uint32_t(below.prims.size()));
        below.prims.push_back({lb, q.id});
      }
      if (!rb.empty()) {
        fresh_above.push_back(uint32_t(above.prims.size()));
        above.prims.push_back({rb, q.id});
      }
    }
    // Events of unclipped references, filtered in order: still sorted (the renumbering keeps
    // the order of references).
    std::vector<KdEvent> kept[2];
    kept[0].reserve(kept_events[0]);
    kept[1].reserve(kept_events[1]);
    for (const KdEvent e : node.events) {
      const uint32_t i = kd_event_prim(e);
      if (side[i] < 2) kept[side[i]].push_back(kd_event_with_prim(e, remap[i]));
    }
    node = SahNode{};
    below.events = merge_fresh(std::move(kept[0]), below.prims, fresh_below);
    above.events = merge_fresh(std::move(kept[1]), above.prims, fresh_above);
  }

  /// Merges the sorted events of the clipped references `fresh` into `kept`.
  static std::vector<KdEvent> merge_fresh(std::vector<KdEvent> kept,
                                          const std::vector<KdPrim>& prims,
                                          const std::vector<uint32_t>& fresh) {
    if (fresh.empty()) return kept;
    std::vector<KdEvent> events;
    events.reserve(6 * fresh.size());
    for (const uint32_t i : fresh) kd_add_events(events, prims[i].box, i);
    std::sort(events.begin(), events.end());
    std::vector<KdEvent> out(kept.size() + events.size());
    std::merge(kept.begin(), kept.end(), events.begin(), events.end(), out.begin());
    return out;
  }

  const PrimitiveSet& set_;
  const KdBuildParams& p_;
  int max_depth_;
};

}  // namespace

KdSubtree build_kd_sah(const PrimitiveSet& prims, std::vector<KdPrim> refs, const Bounds3& bounds,
                       const KdBuildParams& params) {
  const size_t n = refs.size();
  if (n > kKdMaxEventPrims)
    throw Error(
        fmt::format("kdtree: {} primitives, more than the SAH build's {}", n, kKdMaxEventPrims));
  SahNode root;
  root.voxel = bounds;
  root.prims = std::move(refs);
  // Events for all three axes, sorted once (keys are unique: the order is deterministic).
  root.events.reserve(6 * n);
  for (size_t i = 0; i < n; ++i) kd_add_events(root.events, root.prims[i].box, uint32_t(i));
  tbb::parallel_sort(root.events.begin(), root.events.end());
  const SahSplitter split(prims, params, kd_depth_limit(params, n));
  KdSubtree out;
  build_kd_subtree(root, 0, split, params.parallel_min, out);
  return out;
}

}  // namespace penumbra
