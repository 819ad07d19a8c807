#include "penumbra/accel/build/kd_simple_builder.h"

#include <algorithm>
#include <utility>

#include "penumbra/accel/build/kd_build.h"
#include "penumbra/accel/build/kd_clip.h"

namespace penumbra {

namespace {

/// A node under construction: its cell and its references (boxes clipped to the cell).
struct SimpleNode {
  Bounds3 voxel;
  std::vector<KdPrim> prims;
};

class SimpleSplitter {
 public:
  SimpleSplitter(const PrimitiveSet& set, const KdBuildParams& params, int max_depth)
      : set_(set), p_(params), max_depth_(max_depth) {}

  /// Chooses the plane of `node` and fills its children, or returns no plane for a leaf.
  KdPlane operator()(SimpleNode& node, int depth, SimpleNode& below, SimpleNode& above) const {
    const size_t n = node.prims.size();
    if (n <= size_t(p_.max_leaf) || depth >= max_depth_) return {};
    const Bounds3& v = node.voxel;
    KdPlane plane;
    if (p_.criterion == KdCriterion::kGap) plane = kd_gap_plane(node.prims, v);
    if (plane.axis < 0) {  // the spatial median of the longest axis
      plane.axis = v.max_extent_axis();
      plane.pos = 0.5f * (v.lo[plane.axis] + v.hi[plane.axis]);
    }
    const int k = plane.axis;
    if (!(plane.pos > v.lo[k] && plane.pos < v.hi[k])) return {};  // a cell too thin to split
    // Partition; references lying in the plane go below; straddling ones are clipped.
    for (const KdPrim& q : node.prims) {
      switch (classify_box(q.box, k, plane.pos, true)) {
        case KdSide::kBelow:
          below.prims.push_back(q);
          break;
        case KdSide::kAbove:
          above.prims.push_back(q);
          break;
        case KdSide::kBoth: {
          Bounds3 lb, rb;
          split_prim_bounds(set_, q.id, q.box, k, plane.pos, p_.clip, lb, rb);
          if (!lb.empty()) below.prims.push_back({lb, q.id});
          if (!rb.empty()) above.prims.push_back({rb, q.id});
          break;
        }
      }
    }
    if (below.prims.size() == n && above.prims.size() == n) {  // nothing separated: a leaf
      below = SimpleNode{}, above = SimpleNode{};
      return {};
    }
    below.voxel = above.voxel = v;
    below.voxel.hi[k] = above.voxel.lo[k] = plane.pos;
    node = SimpleNode{};
    return plane;
  }

 private:
  const PrimitiveSet& set_;
  const KdBuildParams& p_;
  int max_depth_;
};

}  // namespace

KdPlane kd_gap_plane(const std::vector<KdPrim>& prims, const Bounds3& voxel) {
  KdPlane best;
  float best_width = 0.0f;
  std::vector<std::pair<float, float>> extents(prims.size());
  for (int k = 0; k < 3; ++k) {
    const float lo = voxel.lo[k], hi = voxel.hi[k], w = hi - lo;
    if (!(w > 0.0f)) continue;
    const float window_lo = lo + 0.25f * w, window_hi = hi - 0.25f * w;
    // A gap (g0, g1), cut to the window, against the best so far.
    const auto consider = [&](float g0, float g1) {
      const float a = std::max(g0, window_lo), b = std::min(g1, window_hi);
      const float mid = 0.5f * (a + b);
      if (b - a > best_width && mid > lo && mid < hi) best_width = b - a, best = {k, mid};
    };
    for (size_t i = 0; i < prims.size(); ++i) extents[i] = {prims[i].box.lo[k], prims[i].box.hi[k]};
    std::sort(extents.begin(), extents.end());
    // Sweep the intervals by start, tracking the end of the covered part.
    float cover = lo;
    for (const auto& [s, e] : extents) {
      if (s > cover) consider(cover, s);
      cover = std::max(cover, e);
    }
    if (hi > cover) consider(cover, hi);
  }
  return best;
}

KdSubtree build_kd_simple(const PrimitiveSet& prims, std::vector<KdPrim> refs,
                          const Bounds3& bounds, const KdBuildParams& params) {
  SimpleNode root{bounds, std::move(refs)};
  const SimpleSplitter split(prims, params, kd_depth_limit(params, root.prims.size()));
  KdSubtree out;
  build_kd_subtree(root, 0, split, params.parallel_min, out);
  return out;
}

}  // namespace penumbra
