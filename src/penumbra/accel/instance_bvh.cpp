#include "penumbra/accel/instance_bvh.h"

#include <algorithm>
#include <utility>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/bvh_walk.h"
#include "penumbra/core/timer.h"

namespace penumbra {

namespace {

/// The ray in object space: the same t reaches the same point (the direction is not normalised).
Ray to_object(const Ray& ray, const Transform& to_world, float tmax) {
  const Transform to_object = to_world.inverted();
  Ray r = ray;
  r.o = to_object.point(ray.o);
  r.d = to_object.vector(ray.d);
  r.tmax = tmax;
  return r;
}

}  // namespace

Bounds3 instance_bounds(const Transform& to_world, const Bounds3& object_bounds) {
  if (object_bounds.empty()) return {};
  const Bounds3 b = to_world.bounds(object_bounds);
  // The object-space ray differs from the exact image of the world ray by the rounding of the
  // inverse transform: widen by a few ulps of the box's magnitude so that no hit on the object's
  // own boundary falls outside its instance's box.
  const Vec3 m = max(abs(b.lo), abs(b.hi));
  const float e = gamma(8) * std::max(m.x, std::max(m.y, m.z));
  return {b.lo - Vec3(e), b.hi + Vec3(e)};
}

void InstanceBvh::build(std::vector<InstancedObject> objects, std::vector<Instance> instances) {
  const Timer timer;
  objects_ = std::move(objects);
  instances_ = std::move(instances);
  // One reference per instance of a non-empty object, its box in world space (zeros as +0 so
  // that the build does not depend on the order of min/max reductions).
  PrimRefs refs;
  bounds_ = {};
  for (uint32_t i = 0; i < instances_.size(); ++i) {
    const InstancedObject& o = objects_[instances_[i].object];
    const Bounds3 b = instance_bounds(instances_[i].to_world, o.prims->bounds());
    if (b.empty()) continue;
    refs.refs.push_back(make_prim_ref(b, i));
    refs.bounds.extend(b);
    refs.centroid_bounds.extend(refs.refs.back().centroid2());
  }
  bounds_ = refs.bounds;
  BvhBuildParams params;
  params.max_leaf = 2;  // an instance test is a whole bottom-level traversal: small leaves
  params.traversal_cost = 0.25f;
  BinaryBvh tree = build_binary_bvh(std::move(refs), params);
  nodes_ = std::move(tree.nodes);
  grow_boxes(nodes_);  // for culling at cull_bound(hit.t) (hit.h)
  leaf_ids_.clear();
  for (const PrimRef& r : tree.refs) leaf_ids_.push_back(r.id);
  stats_ = {};
  stats_.nodes = tree.node_count();
  stats_.leaves = tree.leaves;
  stats_.max_depth = tree.max_depth;
  stats_.prim_refs = leaf_ids_.size();
  stats_.bytes = nodes_.capacity() * sizeof(BvhNode) + leaf_ids_.capacity() * sizeof(uint32_t) +
                 instances_.capacity() * sizeof(Instance) +
                 objects_.capacity() * sizeof(InstancedObject);
  stats_.build_ms = timer.elapsed_ms();
}

template <bool kAnyHit, class Cost>
bool InstanceBvh::traverse(const Ray& ray, Hit& hit, Cost cost) const {
  // Bvh's walk; a leaf's "primitives" are instances, each tested by its bottom-level structure
  // on the ray carried into its object space, on (tmin, closest so far): one indirect call per
  // instance visited.
  const PreparedRay pr(ray);
  const auto leaf = [&](uint32_t index, uint32_t count) {
    bool found = false;
    for (uint32_t k = index; k < index + count; ++k) {
      const uint32_t id = leaf_ids_[k];
      const Instance& inst = instances_[id];
      const Accelerator& bottom = *objects_[inst.object].accel;
      // At the t of the closest hit so far, the lower instance wins (hit.h, tie_bound): such an
      // instance's own query may return that very t.
      const bool lower = hit.valid() && id < hit.instance;
      const Ray local = to_object(ray, inst.to_world, lower ? next_float_up(hit.t) : hit.t);
      if constexpr (kAnyHit) {
        if constexpr (Cost::kCounts) {
          if (bottom.occluded_cost(local, *cost.cost)) return true;
        } else if (bottom.occluded(local)) {
          return true;
        }
      } else {
        Hit h;
        bool any;
        if constexpr (Cost::kCounts)
          any = bottom.intersect_cost(local, h, *cost.cost);
        else
          any = bottom.intersect(local, h);
        if (any && (h.t < hit.t || (h.t == hit.t && lower))) {
          hit = h;
          hit.instance = id;
          found = true;
        }
      }
    }
    return found;
  };
  return walk_bvh<kAnyHit>(nodes_, BvhRay(pr), ray.tmin, hit, leaf, cost);
}

bool InstanceBvh::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || nodes_.empty()) return false;
  return traverse<false>(ray, hit);
}

bool InstanceBvh::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || nodes_.empty()) return false;
  return traverse<false>(ray, hit, CostCounter{&cost});
}

bool InstanceBvh::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  if (!traceable(ray) || nodes_.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  return traverse<true>(ray, hit, CostCounter{&cost});
}

bool InstanceBvh::occluded(const Ray& ray) const {
  if (!traceable(ray) || nodes_.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  return traverse<true>(ray, hit);
}

}  // namespace penumbra
