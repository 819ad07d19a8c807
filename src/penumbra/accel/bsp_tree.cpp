#include "penumbra/accel/bsp_tree.h"

#include <algorithm>
#include <cmath>

#include "penumbra/core/timer.h"

// Why a node may test the whole original primitive of a fragment.
//
// A fragment F of polygon P stored at node N is P ∩ R(N) ∩ H(N): the part of P inside N's convex
// region R(N), lying in N's plane H(N) (P's own plane). A ray that does not lie in H(N) meets it at
// one point x = o + t d. The ray's segment inside R(N) is [t0, t1], so x ∈ R(N) exactly when
// t ∈ [t0, t1]; and the watertight test hits P at t exactly when x ∈ P. Hence "P is hit at a t in
// [t0, t1]" means "x ∈ P ∩ R(N) ∩ H(N) = F": testing P and keeping the hit only inside the segment
// is testing F. (The traversal keeps hits on the sub-segment within eps of H(N), below, which
// holds the crossing whenever [t0, t1] does.) The fragments of P tile it and the regions of the
// nodes storing them have disjoint interiors, so every point of P is accepted at the node of the
// fragment holding it, and (up to points on a shared region boundary) nowhere else. A ray lying in
// H(N) never hits P in exact arithmetic (the watertight test's determinant is zero).
//
// Rounding: planes are stored in float and evaluated in float, hit points carry the triangle
// test's rounding, and the build puts a vertex within eps_b = kBspBuildEps * scale of a plane on
// it (scale = the largest absolute scene coordinate rather than the diagonal: float rounding grows
// with the coordinates' magnitude, so a small model far from the origin needs the larger unit). So
// the traversal widens every region by eps = kBspTraversalEps * (scale + |o|max), ten times more:
// the lower child takes the ray where its signed distance is <= eps, the upper one where it is >=
// -eps, and the plane's primitives are tested on the part within eps of the plane (always, for a
// ray parallel to the plane within eps of it, where float rounding can make the watertight test
// report a hit; brute force then reports it too). Widening only makes the traversal visit and
// accept more; every accepted hit is a true hit of the primitive on (tmin, hit.t), and accepting
// the same point at two neighbouring nodes cannot change the closest hit. Leaves test their objects
// on the whole ray, as brute force does.

namespace penumbra {

namespace {

/// Marks a deferred test of a node's own primitives on the traversal stack.
constexpr uint32_t kPlaneTask = 0x80000000u;

/// A deferred subtree (or plane test) and the ray's segment in it.
struct StackEntry {
  uint32_t node;
  float t0, t1;
};

/// Clips the ray's (tmin, tmax) to `b` widened by `eps`; false when nothing is left.
bool clip_to_box(const Ray& r, const Bounds3& b, float eps, float tmax, float& t0, float& t1) {
  t0 = r.tmin, t1 = tmax;
  for (int i = 0; i < 3; ++i) {
    const float lo = b.lo[i] - eps, hi = b.hi[i] + eps;
    if (r.d[i] == 0.0f) {
      if (!(r.o[i] >= lo && r.o[i] <= hi)) return false;
      continue;
    }
    float ta = (lo - r.o[i]) / r.d[i], tb = (hi - r.o[i]) / r.d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

}  // namespace

BspTree::BspTree(const ParamList& params) {
  params_ = read_bsp_build_params(params);
  params.check_all_used();
  name_ = params.to_string();
}

void BspTree::build(const PrimitiveSet& prims) {
  const Timer timer;
  prims_ = &prims;
  tree_ = {};  // free the previous tree first
  tree_ = build_bsp(prims, params_);
  bounds_ = prims.bounds();
  scale_ = float(tree_.scale);
  // Triangle-only sets: the vertices in reference order, so that a node's tests read one
  // contiguous block instead of going through the primitive set.
  tris_.clear();
  if (prims.all_triangles()) {
    tris_.resize(3 * tree_.refs.size());
    for (size_t i = 0; i < tree_.refs.size(); ++i)
      std::copy_n(prims.triangle(tree_.refs[i]), 3, &tris_[3 * i]);
  }
  tris_.shrink_to_fit();
  stats_ = {};
  stats_.nodes = tree_.nodes.size() + tree_.empty_cells;
  stats_.leaves = tree_.leaves;
  stats_.max_depth = tree_.max_depth;
  stats_.prim_refs = tree_.refs.size();
  stats_.bytes = tree_.nodes.capacity() * sizeof(BspNode) +
                 tree_.refs.capacity() * sizeof(uint32_t) + tris_.capacity() * sizeof(Vec3);
  const double per = tree_.planar ? double(tree_.fragments) / double(tree_.planar) : 0.0;
  stats_.extra = {{"fragments", double(tree_.fragments)},
                  {"fragments_per_triangle", per},
                  {"object_refs", double(tree_.object_refs)},
                  {"empty_cells", double(tree_.empty_cells)},
                  {"capped_leaves", double(tree_.capped_leaves)}};
  stats_.build_ms = timer.elapsed_ms();
}

template <bool kAnyHit, bool kTriangles, class Cost>
bool BspTree::test_refs(const BspNode& node, const PreparedRay& pr, float lo, float hi, Hit& hit,
                        Cost cost) const {
  const float upper = hi + std::fabs(hi) * 0x1p-22f;  // a little wider: it may only accept more
  bool found = false;
  for (uint32_t i = node.first; i < node.first + node.count; ++i) {
    cost.prims(1);
    bool h;
    if constexpr (kTriangles) {
      const Vec3* v = &tris_[3 * size_t(i)];
      const float tmax = std::min(tie_bound(hit, tree_.refs[i]), upper);
      float t, u, w;
      h = intersect_triangle(pr, v[0], v[1], v[2], pr.ray.tmin, tmax, t, u, w) && t >= lo;
      if (h) hit = {t, u, w, tree_.refs[i]};
    } else {
      Hit c = hit;  // its t and id decide a tie (tie_bound), unless the cell ends first
      if (upper < c.t) c = Hit{upper};
      h = prims_->intersect(tree_.refs[i], pr, c) && c.t >= lo;
      if (h) hit = c;
    }
    if (h) {
      if constexpr (kAnyHit) return true;
      found = true;
    }
  }
  return found;
}

template <bool kAnyHit, bool kTriangles, class Cost>
bool BspTree::traverse(const PreparedRay& pr, Hit& hit, Cost cost) const {
  const Ray& ray = pr.ray;
  const float eps = float(kBspTraversalEps) * (scale_ + max_component(abs(ray.o)));
  float t0, t1;
  if (!clip_to_box(ray, bounds_, eps, hit.t, t0, t1)) return false;
  StackEntry stack[kBspStackSize];
  int sp = 0;
  uint32_t index = 0;
  bool found = false;
  while (true) {
    {
      const BspNode& node = tree_.nodes[index];
      cost.node();
      if (node.is_leaf()) {
        // Objects, or the fragments left by the depth cap: the whole ray, as brute force does.
        if (test_refs<kAnyHit, kTriangles>(node, pr, -kInfinity, kInfinity, hit, cost)) {
          if constexpr (kAnyHit) return true;
          found = true;
        }
        goto pop;
      }
      // Signed distance to the plane along the ray: s(t) = a + b t. The lower child's widened
      // region holds the ray where s <= eps, the upper child's where s >= -eps.
      const float a = dot(node.n, ray.o) - node.d, b = dot(node.n, ray.d);
      const float s0 = a + b * t0, s1 = a + b * t1;
      if (std::min(s0, s1) > eps || std::max(s0, s1) < -eps) {  // one side only: no division
        const uint32_t next = node.child[s0 > 0.0f ? 1 : 0];
        if (next == kBspEmpty) goto pop;
        index = next;
        continue;
      }
      uint32_t near, far;
      float near_end, far_start;
      if (b != 0.0f) {
        const float t_lower = (eps - a) / b, t_upper = (-eps - a) / b;  // s = eps, s = -eps
        const bool rising = b > 0.0f;  // from below to above: the lower child comes first
        near = node.child[rising ? 0 : 1], far = node.child[rising ? 1 : 0];
        near_end = rising ? t_lower : t_upper;
        far_start = rising ? t_upper : t_lower;
      } else {  // parallel, within eps of the plane: both sides, the origin's first
        const bool above = a >= 0.0f;
        near = node.child[above ? 1 : 0], far = node.child[above ? 0 : 1];
        near_end = kInfinity, far_start = -kInfinity;
      }
      const float near_t1 = std::min(t1, near_end), far_t0 = std::max(t0, far_start);
      const bool in_near = t0 <= near_t1, in_far = far_t0 <= t1;
      // Both parts non-empty: the ray comes within eps of the plane on [far_t0, near_t1].
      const bool on_plane = in_near && in_far && node.count != 0;
      if constexpr (kAnyHit) {
        if (on_plane && test_refs<true, kTriangles>(node, pr, far_t0, near_t1, hit, cost))
          return true;
      }
      const bool go_near = in_near && near != kBspEmpty, go_far = in_far && far != kBspEmpty;
      if (go_near) {  // near child now; the plane, then the far child, when it returns
        if (go_far) stack[sp++] = {far, far_t0, t1};
        if (!kAnyHit && on_plane) stack[sp++] = {index | kPlaneTask, far_t0, near_t1};
        index = near, t1 = near_t1;
        continue;
      }
      if (!kAnyHit && on_plane &&
          test_refs<false, kTriangles>(node, pr, far_t0, near_t1, hit, cost))
        found = true;
      if (go_far && far_t0 <= hit.t) {
        index = far, t0 = far_t0, t1 = std::min(t1, hit.t);
        continue;
      }
    }
  pop:
    // The next deferred entry that may still hold a closer hit.
    while (true) {
      if (sp == 0) return found;
      const StackEntry e = stack[--sp];
      if (e.t0 > hit.t) continue;
      if (e.node & kPlaneTask) {
        if (test_refs<false, kTriangles>(tree_.nodes[e.node & ~kPlaneTask], pr, e.t0, e.t1, hit,
                                     cost))
          found = true;
        continue;
      }
      index = e.node, t0 = e.t0, t1 = std::min(e.t1, hit.t);
      break;
    }
  }
}

bool BspTree::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  if (tree_.nodes.empty()) return false;
  const PreparedRay pr(ray);
  return tris_.empty() ? traverse<false, false>(pr, hit) : traverse<false, true>(pr, hit);
}

bool BspTree::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || tree_.nodes.empty()) return false;
  const PreparedRay pr(ray);
  const CostCounter c{&cost};
  return tris_.empty() ? traverse<false, false>(pr, hit, c) : traverse<false, true>(pr, hit, c);
}

bool BspTree::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  if (!traceable(ray) || tree_.nodes.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  const PreparedRay pr(ray);
  const CostCounter c{&cost};
  return tris_.empty() ? traverse<true, false>(pr, hit, c) : traverse<true, true>(pr, hit, c);
}

bool BspTree::occluded(const Ray& ray) const {
  if (!traceable(ray)) return false;
  if (tree_.nodes.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  const PreparedRay pr(ray);
  return tris_.empty() ? traverse<true, false>(pr, hit) : traverse<true, true>(pr, hit);
}

}  // namespace penumbra
