#pragma once
/// `kdtree`: a kd-tree (Bentley 1975, "Multidimensional binary search trees used for associative
/// searching") over the primitives: axis-aligned split planes chosen by the SAH, the spatial
/// median or the largest gap; straddling primitives are referenced on both sides, clipped to each
/// child. Stored as a flat array of 8-byte nodes and a flat reference array; traversed front to
/// back with the tmin/tmax stack of Pharr, Jakob, Humphreys ("Physically Based Rendering", 3rd
/// ed., section 4.4.3), itself Havran's recursive algorithm ("Heuristic Ray Shooting
/// Algorithms", PhD thesis, 2000) made iterative. A ray that starts inside the tree first
/// descends to its origin's leaf without branches, by the side of each plane the origin lies on
/// (kdtree.cpp; docs/accel/kdtree.md, "The first descent").
///
/// Parameters (`kdtree:sah,ci=0.5`); the defaults are the fastest of a sweep on bunny,
/// human_blend, cylinder_engine and spheres-1m (docs/accel/kdtree.md):
///   sah | median | gap   the split criterion (default sah; see kd_sah_builder.h and
///                        kd_simple_builder.h)
///   ct=X           cost of traversing an inner node, 0..1000 (default 1)
///   ci=X           cost of one leaf test, 0.01..1000 (default 0.4): a block of four triangles
///                  in triangle-only sets (the SAH counts blocks), else one primitive; only
///                  ci / ct matters
///   empty_bonus=X  a split with an empty side costs (1 - X) times its SAH cost, 0..0.99
///                  (default 0.1; Wald and Havran's lambda = 0.8 is empty_bonus=0.2)
///   leaf=N         nodes with at most N references become leaves, 0..1024 (default 0 with sah,
///                  where the cost alone decides; 8 with median and gap)
///   depth=N        deepest level, 1..64 (default round(8 + 1.3 log2 N), as pbrt)
///   clip=0         bound straddling primitives by their box cut at the plane instead of clipping
///                  the polygon (for comparison; default 1)
#include <span>
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/core/array_allocator.h"
#include "penumbra/accel/build/kd_node.h"
#include "penumbra/accel/triangle_blocks.h"
#include "penumbra/core/params.h"

namespace penumbra {

/// Kd-tree over any primitive set. When the set holds only triangles, each leaf's references
/// start at a multiple of four (padded with kNoPrim) and the triangles are copied into blocks of
/// four in reference order (triangle_blocks.h), tested four at a time.
class KdTree final : public Accelerator {
 public:
  /// Reads the criterion and parameters from `params` (see the file comment); throws Error on
  /// bad or unknown ones.
  explicit KdTree(const ParamList& params);
  std::string name() const override { return name_; }
  void build(const PrimitiveSet& prims) override;
  bool intersect(const Ray& ray, Hit& hit) const override;
  bool occluded(const Ray& ray) const override;
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const override;
  AccelStats stats() const override { return stats_; }

  /// The settings in use.
  const KdBuildParams& params() const { return params_; }
  /// The nodes, root first (empty when nothing was built).
  std::span<const KdNode> nodes() const { return {nodes_.data(), nodes_.size()}; }
  /// Primitive ids in reference order (leaves index into this; kNoPrim pads the leaves of
  /// triangle-only sets to multiples of four).
  std::span<const uint32_t> refs() const { return {refs_.data(), refs_.size()}; }
  /// The root cell.
  const Bounds3& bounds() const { return bounds_; }

 private:
  template <bool kAnyHit, bool kTriangles, class Cost = NoCost>
  bool traverse(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;

  std::string name_;
  KdBuildParams params_;
  const PrimitiveSet* prims_ = nullptr;
  Bounds3 bounds_;
  /// bounds_ as [lo, hi][axis], so that a ray's entry and exit planes are loads indexed by its
  /// direction's signs (a branch on each sign mispredicted half the random rays).
  float planes_[2][3] = {};
  float max_extent_ = 0;  ///< the largest extent of a referenced primitive's box (cull_slack)
  std::vector<KdNode, ArrayAllocator<KdNode>> nodes_;
  std::vector<uint32_t, ArrayAllocator<uint32_t>> refs_;
  TriangleBlocks blocks_;  ///< refs_ / 4 blocks when every primitive is a triangle, or none
  AccelStats stats_;
};

}  // namespace penumbra
