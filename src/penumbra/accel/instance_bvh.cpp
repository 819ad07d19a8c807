#include "penumbra/accel/instance_bvh.h"

#include <algorithm>
#include <utility>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/bvh_ray.h"
#include "penumbra/core/timer.h"

namespace penumbra {

namespace {

/// A deferred subtree: its node's payload (index, count) and its entry distance.
struct StackEntry {
  uint32_t index, count;
  float t;
};

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
    PrimRef r;
    r.lo = b.lo + Vec3(0.0f), r.hi = b.hi + Vec3(0.0f), r.id = i, r.pad = 0;
    refs.refs.push_back(r);
    refs.bounds.extend(b);
    refs.centroid_bounds.extend(r.centroid2());
  }
  bounds_ = refs.bounds;
  BvhBuildParams params;
  params.max_leaf = 2;  // an instance test is a whole bottom-level traversal: small leaves
  params.traversal_cost = 0.25f;
  BinaryBvh tree = build_binary_bvh(std::move(refs), params);
  nodes_ = std::move(tree.nodes);
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

template <bool kAnyHit>
bool InstanceBvh::traverse(const Ray& ray, Hit& hit) const {
  // The same front-to-back walk as Bvh::traverse; a leaf's "primitives" are instances, each
  // tested by its bottom-level structure on the ray carried into its object space.
  const PreparedRay pr(ray);
  const BvhRay r(pr);
  const float tmin = ray.tmin;
  float entry;
  if (!hit_node(nodes_[0], r, tmin, hit.t, entry)) return false;
  StackEntry stack[kBvhStackSize];
  int sp = 0;
  uint32_t index = nodes_[0].index, count = nodes_[0].count;
  bool found = false;
  while (true) {
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
    // Leaf: each instance's bottom level on (tmin, closest so far); one indirect call per
    // instance visited.
    for (uint32_t k = index; k < index + count; ++k) {
      const uint32_t id = leaf_ids_[k];
      const Instance& inst = instances_[id];
      const Accelerator& bottom = *objects_[inst.object].accel;
      const Ray local = to_object(ray, inst.to_world, hit.t);
      if constexpr (kAnyHit) {
        if (bottom.occluded(local)) return true;
      } else {
        Hit h;
        if (bottom.intersect(local, h) && h.t < hit.t) {
          hit = h;
          hit.instance = id;
          found = true;
        }
      }
    }
  pop:
    do {
      if (sp == 0) return found;
      --sp;
    } while (stack[sp].t > hit.t);
    index = stack[sp].index, count = stack[sp].count;
  }
}

bool InstanceBvh::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || nodes_.empty()) return false;
  return traverse<false>(ray, hit);
}

bool InstanceBvh::occluded(const Ray& ray) const {
  if (!traceable(ray) || nodes_.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  return traverse<true>(ray, hit);
}

}  // namespace penumbra
