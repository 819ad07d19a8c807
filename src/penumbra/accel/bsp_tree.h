#pragma once
/// `bsp`: a 3D binary space partition by auto-partition (de Berg, Cheong, van Kreveld, Overmars
/// 2008, "Computational Geometry: Algorithms and Applications", 3rd ed., ch. 12; Paterson, Yao
/// 1990, "Efficient binary space partitions for hidden-surface removal and solid modeling"). Each
/// inner node splits space by the plane of one of its triangles or parallelograms; polygons cut by
/// it become fragments on both sides, polygons lying in it are stored at the node. The leaves are
/// convex cells, almost all empty; spheres and degenerate polygons (no plane) are kept as objects
/// in the leaves they reach. See build/bsp_builder.h for the build.
///
/// Parameters (`bsp:order=fewest-cuts,candidates=16`):
///   order=O          random (default; 3DRANDOMBSP with seed=), first (input order) or
///                    fewest-cuts (the sampled candidate plane cutting the fewest fragments)
///   seed=N           permutation seed for random and fewest-cuts (default 1)
///   candidates=N     fewest-cuts: planes scored per node, 1..1024 (default 32)
///   depth=N          depth cap, 1..1024 (default 256); capped nodes become leaves holding their
///                    fragments' primitives, tested like brute force
///   max_fragments=N  the build fails with an Error beyond this many fragments plus object
///                    references (default 2^24), instead of exhausting memory
///
/// Traversal is front to back: the child on the ray's near side, then the node's own primitives
/// where the ray crosses the plane, then the far child. A primitive stored at a node stands for
/// its fragment there: its hit counts only if it falls in the ray's segment inside the node's
/// region (see bsp_tree.cpp for why that is exactly the fragment).
#include <span>
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/accel/build/bsp_builder.h"
#include "penumbra/core/params.h"

namespace penumbra {

/// Auto-partition BSP tree over any primitive set.
class BspTree final : public Accelerator {
 public:
  /// Reads the parameters above from `params`; throws Error on bad or unknown ones.
  explicit BspTree(const ParamList& params);
  std::string name() const override { return name_; }
  void build(const PrimitiveSet& prims) override;
  bool intersect(const Ray& ray, Hit& hit) const override;
  bool occluded(const Ray& ray) const override;
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const override;
  AccelStats stats() const override { return stats_; }

  /// The nodes, root at 0 (empty when nothing was built).
  std::span<const BspNode> nodes() const { return {tree_.nodes.data(), tree_.nodes.size()}; }
  /// Primitive ids; each node's coplanar or leaf primitives are a contiguous range.
  std::span<const uint32_t> refs() const { return {tree_.refs.data(), tree_.refs.size()}; }
  /// The build settings read from the parameters.
  const BspBuildParams& build_params() const { return params_; }

 private:
  template <bool kAnyHit, bool kTriangles, class Cost = NoCost>
  bool traverse(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;
  /// Tests the node's references, keeping only hits with t in [lo, hi] (and below hit.t).
  template <bool kAnyHit, bool kTriangles, class Cost>
  bool test_refs(const BspNode& node, const PreparedRay& pr, float lo, float hi, Hit& hit,
                 Cost cost) const;

  std::string name_;
  BspBuildParams params_;
  const PrimitiveSet* prims_ = nullptr;
  BspBuildResult tree_;
  std::vector<Vec3> tris_;  ///< triangle-only sets: three vertices per reference, else empty
  Bounds3 bounds_;          ///< scene bounds, the root's region
  float scale_ = 0;         ///< largest absolute scene coordinate
  AccelStats stats_;
};

}  // namespace penumbra
