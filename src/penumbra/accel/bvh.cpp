#include "penumbra/accel/bvh.h"

#include <utility>

#include "penumbra/accel/bvh_ray.h"
#include "penumbra/core/timer.h"

namespace penumbra {

namespace {

/// A deferred subtree: its node's payload (index, count) and its entry distance.
struct StackEntry {
  uint32_t index, count;
  float t;
};

}  // namespace

Bvh::Bvh(const ParamList& params) {
  params_ = read_bvh_build_params(params);
  params.check_all_used();
  name_ = params.to_string();
}

void Bvh::build(const PrimitiveSet& prims) {
  const Timer timer;
  prims_ = &prims;
  BinaryBvh tree = build_binary_bvh(make_prim_refs(prims), params_);
  const size_t node_count = tree.node_count();
  nodes_ = std::move(tree.nodes);
  leaf_.build(prims, tree.refs);
  stats_ = {};
  stats_.nodes = node_count;
  stats_.leaves = tree.leaves;
  stats_.max_depth = tree.max_depth;
  stats_.prim_refs = tree.refs.size();
  stats_.bytes = nodes_.capacity() * sizeof(BvhNode) + leaf_.bytes();
  stats_.build_ms = timer.elapsed_ms();
}

template <bool kAnyHit, bool kTriangles>
bool Bvh::traverse(const PreparedRay& pr, Hit& hit) const {
  const BvhRay r(pr);
  const float tmin = pr.ray.tmin;
  float entry;
  if (!hit_node(nodes_[0], r, tmin, hit.t, entry)) return false;
  StackEntry stack[kBvhStackSize];
  int sp = 0;
  uint32_t index = nodes_[0].index, count = nodes_[0].count;
  bool found = false;
  while (true) {
    // Inner nodes: test both children (one cache line), go to the nearer, defer the other.
    // Plain branches: coherent rays predict them well, and scalar slab tests have a shorter
    // latency than a two-box SIMD test with its shuffles (measured: 1.5x on primary rays).
    while (count == 0) {
      const BvhNode& a = nodes_[index];
      const BvhNode& b = nodes_[index + 1];
      float ta, tb;
      const bool ha = hit_node(a, r, tmin, hit.t, ta);
      const bool hb = hit_node(b, r, tmin, hit.t, tb);
      if (ha && hb) {
        const bool b_first = tb < ta;
        const BvhNode& first = b_first ? b : a;
        const BvhNode& second = b_first ? a : b;
        stack[sp++] = {second.index, second.count, b_first ? ta : tb};
        index = first.index, count = first.count;
      } else if (ha || hb) {
        const BvhNode& only = ha ? a : b;
        index = only.index, count = only.count;
      } else {
        goto pop;
      }
    }
    // Leaf: test its primitives; each hit shrinks hit.t.
    if (leaf_.intersect<kAnyHit, kTriangles>(*prims_, pr, index, count, hit)) {
      if constexpr (kAnyHit) return true;
      found = true;
    }
  pop:
    // The next deferred subtree that may still hold a closer hit.
    do {
      if (sp == 0) return found;
      --sp;
    } while (stack[sp].t > hit.t);
    index = stack[sp].index, count = stack[sp].count;
  }
}

bool Bvh::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  return leaf_.triangles() ? traverse<false, true>(pr, hit) : traverse<false, false>(pr, hit);
}

bool Bvh::occluded(const Ray& ray) const {
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  Hit hit;
  hit.t = ray.tmax;
  return leaf_.triangles() ? traverse<true, true>(pr, hit) : traverse<true, false>(pr, hit);
}

}  // namespace penumbra
