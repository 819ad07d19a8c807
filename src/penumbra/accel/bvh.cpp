#include "penumbra/accel/bvh.h"

#include <utility>

#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"
#include "penumbra/accel/bvh_ray.h"

namespace penumbra {

namespace {

/// A deferred subtree: its node's payload (index, count) and its entry distance.
struct StackEntry {
  uint32_t index, count;
  float t;
};

}  // namespace

Bvh::Bvh(const ParamList& params) {
  params_.max_leaf = int(params.get_int("leaf", 8, 1, 64));
  params_.bins = int(params.get_int("bins", 16, 2, kMaxBins));
  params_.traversal_cost = float(params.get_real("trav", 1.0, 0.0, 100.0));
  params.check_all_used();
  name_ = params.to_string();
}

void Bvh::build(const PrimitiveSet& prims) {
  const Timer timer;
  prims_ = &prims;
  BinaryBvh tree = build_binary_bvh(make_prim_refs(prims), params_);
  const size_t node_count = tree.node_count();
  nodes_ = std::move(tree.nodes);
  const size_t n = tree.refs.size();
  ids_.resize(n);
  tris_.clear();
  if (prims.all_triangles()) tris_.resize(3 * n);
  // Leaf order ids and, for triangle-only sets, the vertices copied into leaf order.
  parallel_for_range(
      n,
      [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
          const uint32_t id = tree.refs[i].id;
          ids_[i] = id;
          if (!tris_.empty()) {
            const Vec3* v = prims.triangle(id);
            tris_[3 * i] = v[0], tris_[3 * i + 1] = v[1], tris_[3 * i + 2] = v[2];
          }
        }
      },
      4096);
  stats_ = {};
  stats_.nodes = node_count;
  stats_.leaves = tree.leaves;
  stats_.max_depth = tree.max_depth;
  stats_.prim_refs = n;
  stats_.bytes = nodes_.capacity() * sizeof(BvhNode) + ids_.capacity() * sizeof(uint32_t) +
                 tris_.capacity() * sizeof(Vec3);
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
    while (count == 0) {
      const BvhNode* pair = &nodes_[index];
      float ta, tb;
      const unsigned mask = hit_pair(pair, r, tmin, hit.t, ta, tb);
      if (mask == 0) goto pop;
      const unsigned first = tb < ta;  // a missed child has distance +inf
      const BvhNode& other = pair[first ^ 1u];
      stack[sp] = {other.index, other.count, first ? ta : tb};
      sp += mask == 3u;
      __builtin_prefetch(&nodes_[other.index]);
      index = pair[first].index, count = pair[first].count;
    }
    // Leaf: test its primitives; each hit shrinks hit.t.
    for (uint32_t i = index; i < index + count; ++i) {
      bool h;
      if constexpr (kTriangles) {
        const Vec3* v = &tris_[3 * size_t(i)];
        float t, u, w;
        h = intersect_triangle(pr, v[0], v[1], v[2], tmin, hit.t, t, u, w);
        if (h) hit = {t, u, w, ids_[i]};
      } else {
        h = prims_->intersect(ids_[i], pr, hit);
      }
      if (h) {
        if constexpr (kAnyHit) return true;
        found = true;
      }
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
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  return tris_.empty() ? traverse<false, false>(pr, hit) : traverse<false, true>(pr, hit);
}

bool Bvh::occluded(const Ray& ray) const {
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  Hit hit;
  hit.t = ray.tmax;
  return tris_.empty() ? traverse<true, false>(pr, hit) : traverse<true, true>(pr, hit);
}

}  // namespace penumbra
