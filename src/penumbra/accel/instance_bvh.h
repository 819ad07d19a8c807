#pragma once
/// The top level of a two-level structure: a binary BVH over instances, each a placement (an
/// affine object-to-world transform) of a shared bottom-level structure built once over its
/// object's primitives in object space. Any registered Accelerator serves as the bottom level.
///
/// A ray is carried into object space (origin and direction by the inverse transform, the
/// direction not renormalised), so the ray parameter t of an object-space hit is the world-space
/// t of the same point: t, tmin and tmax need no conversion and hits of different instances
/// compare directly. A scene of N copies of an M-primitive object stores the M primitives and
/// their structure once, plus N transforms and a tree over N boxes.
#include <cstdint>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/accel/build/bvh_node.h"
#include "penumbra/core/transform.h"

namespace penumbra {

/// One placement of an object: which bottom-level structure, and where.
struct Instance {
  uint32_t object = 0;  ///< index into the objects passed to InstanceBvh::build
  Transform to_world;   ///< object space to world space (affine)
};

/// A bottom-level structure and its primitives (object space), shared by every instance.
struct InstancedObject {
  const Accelerator* accel = nullptr;  ///< built over `prims`
  const PrimitiveSet* prims = nullptr;
};

/// Binary BVH (binned SAH) over instances' world-space boxes; queries as Accelerator's, with
/// Hit::instance set on a hit. The objects must outlive it. Queries are const and thread-safe.
class InstanceBvh {
 public:
  /// Builds over `instances` of `objects`; an instance of an empty object is never hit.
  void build(std::vector<InstancedObject> objects, std::vector<Instance> instances);
  /// Closest hit on (ray.tmin, ray.tmax): fills `hit` (prim: an id of the object's primitive
  /// set; instance: an index into instances()) and returns true when there is one.
  bool intersect(const Ray& ray, Hit& hit) const;
  /// True when any instance blocks `ray` on (ray.tmin, ray.tmax).
  bool occluded(const Ray& ray) const;
  /// intersect, adding the top level's nodes and each visited instance's bottom-level cost.
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const;
  /// occluded, adding to `cost` the work of this level and of the instances' structures.
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const;

  /// The instances, in the order given to build().
  const std::vector<Instance>& instances() const { return instances_; }
  /// The objects, in the order given to build().
  const std::vector<InstancedObject>& objects() const { return objects_; }
  /// World bounds of every instance.
  const Bounds3& bounds() const { return bounds_; }
  /// The top level's statistics (its nodes and instance records; bytes exclude the objects).
  AccelStats stats() const { return stats_; }

 private:
  template <bool kAnyHit, class Cost = NoCost>
  bool traverse(const Ray& ray, Hit& hit, Cost cost = {}) const;

  std::vector<InstancedObject> objects_;
  std::vector<Instance> instances_;
  BvhNodeArray nodes_;
  std::vector<uint32_t> leaf_ids_;  ///< instance indices in leaf order
  Bounds3 bounds_;
  AccelStats stats_;
};

/// Conservative world box of `object_bounds` under `to_world`: the box of the eight transformed
/// corners, widened by the rounding of the transform in float (a few ulps of its magnitude).
Bounds3 instance_bounds(const Transform& to_world, const Bounds3& object_bounds);

}  // namespace penumbra
