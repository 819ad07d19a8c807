#pragma once
/// `bvh`: a binary bounding volume hierarchy built top-down with binned SAH splits (Wald 2007,
/// "On fast Construction of SAH-based Bounding Volume Hierarchies"), stored as a flat array of
/// 32-byte nodes with adjacent children, traversed front to back with a fixed-size stack.
///
/// Parameters (`bvh:leaf=4,bins=32`):
///   leaf=N   most primitives per leaf, 1..64 (default 8); the SAH decides below that
///   bins=N   SAH bins per axis, 2..64 (default 16)
///   trav=X   cost of visiting an inner node relative to one primitive test, 0..100 (default 2;
///            measured: as fast as 1 and fewer, fuller leaves, so a faster build)
#include <span>
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/leaf_prims.h"
#include "penumbra/core/params.h"

namespace penumbra {

/// Binary BVH over any primitive set; triangles are copied into leaf order for cache-friendly
/// leaf tests when the set holds only triangles.
class Bvh final : public Accelerator {
 public:
  /// Reads leaf, bins and trav from `params` (see the file comment); throws Error on bad values.
  explicit Bvh(const ParamList& params);
  std::string name() const override { return name_; }
  void build(const PrimitiveSet& prims) override;
  bool intersect(const Ray& ray, Hit& hit) const override;
  bool occluded(const Ray& ray) const override;
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const override;
  AccelStats stats() const override { return stats_; }

  /// The nodes: root at 0, padding at 1, child pairs from 2 (empty when nothing was built).
  std::span<const BvhNode> nodes() const { return {nodes_.data(), nodes_.size()}; }
  /// Primitive ids in leaf order (leaves index into this).
  std::span<const uint32_t> leaf_prims() const { return leaf_.ids(); }

 private:
  template <bool kAnyHit, bool kTriangles, class Cost = NoCost>
  bool traverse(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;

  std::string name_;
  BvhBuildParams params_;
  const PrimitiveSet* prims_ = nullptr;
  BvhNodeArray nodes_;
  LeafPrims leaf_;
  AccelStats stats_;
};

}  // namespace penumbra
