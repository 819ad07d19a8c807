#include "penumbra/accel/bvh.h"

#include <utility>

#include "penumbra/accel/bvh_walk.h"
#include "penumbra/core/timer.h"

namespace penumbra {

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
  grow_boxes(nodes_);  // for culling at cull_bound(hit.t) (hit.h)
  leaf_.build(prims, tree.refs);
  stats_ = {};
  stats_.nodes = node_count;
  stats_.leaves = tree.leaves;
  stats_.max_depth = tree.max_depth;
  stats_.prim_refs = tree.refs.size();
  stats_.bytes = nodes_.capacity() * sizeof(BvhNode) + leaf_.bytes();
  stats_.build_ms = timer.elapsed_ms();
}

template <bool kAnyHit, bool kTriangles, class Cost>
bool Bvh::traverse(const PreparedRay& pr, Hit& hit, Cost cost) const {
  // Leaf: test its primitives; each hit shrinks hit.t.
  return walk_bvh<kAnyHit>(
      nodes_, BvhRay(pr), pr.ray.tmin, hit,
      [&](uint32_t index, uint32_t count) {
        return leaf_.intersect<kAnyHit, kTriangles>(*prims_, pr, index, count, hit, cost);
      },
      cost);
}

bool Bvh::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  const PreparedRay pr(ray);
  return leaf_.triangles() ? traverse<false, true>(pr, hit) : traverse<false, false>(pr, hit);
}

bool Bvh::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || nodes_.empty()) return false;
  const PreparedRay pr(ray);
  const CostCounter c{&cost};
  return leaf_.triangles() ? traverse<false, true>(pr, hit, c) : traverse<false, false>(pr, hit, c);
}

bool Bvh::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  if (!traceable(ray) || nodes_.empty()) return false;
  const PreparedRay pr(ray);
  Hit hit;
  hit.t = ray.tmax;
  const CostCounter c{&cost};
  return leaf_.triangles() ? traverse<true, true>(pr, hit, c) : traverse<true, false>(pr, hit, c);
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
