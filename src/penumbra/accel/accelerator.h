#pragma once
/// The interface every spatial data structure for ray shooting implements.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/accel/traversal_cost.h"
#include "penumbra/core/ray.h"
#include "penumbra/core/target.h"
#include "penumbra/geometry/hit.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// Size and shape of a built structure, reported by `render` and `accel-bench`.
struct AccelStats {
  size_t nodes = 0;            ///< all nodes, inner and leaf
  size_t leaves = 0;           ///< leaf nodes (or cells)
  size_t max_depth = 0;        ///< deepest leaf (root at depth 0)
  size_t prim_refs = 0;        ///< primitive references stored in leaves
  size_t bytes = 0;            ///< memory of the structure, excluding the primitives themselves
  double build_ms = 0;         ///< wall time of the build
  /// Structure-specific figures (e.g. "fragments"), printed after the common ones.
  std::vector<std::pair<std::string, double>> extra;

  /// Mean primitive references per leaf.
  double mean_prims_per_leaf() const { return leaves ? double(prim_refs) / double(leaves) : 0.0; }
};

/// What a batch of rays is like: neighbours in the batch following nearly the same path through
/// a structure (camera rays in pixel order, and rays starting at their hits), or not. Interleaving
/// pays for the latter and not the former (docs/accel.md, "Batch queries").
enum class BatchOrder { kIncoherent, kCoherent };

/// A spatial data structure over a PrimitiveSet, answering closest-hit and any-hit queries.
/// The primitive set must outlive the structure. Queries are const and thread-safe.
class Accelerator {
 public:
  virtual ~Accelerator() = default;

  /// The registered name with its parameters, e.g. "bvh" or "kdtree:sah".
  virtual std::string name() const = 0;
  /// Builds over `prims` (replacing any previous build).
  virtual void build(const PrimitiveSet& prims) = 0;
  /// Closest hit on (ray.tmin, ray.tmax); fills `hit` and returns true when there is one.
  virtual bool intersect(const Ray& ray, Hit& hit) const = 0;
  /// True when anything is hit on (ray.tmin, ray.tmax).
  virtual bool occluded(const Ray& ray) const = 0;
  /// intersect(rays[i], hits[i]) for every i, with the same results bit for bit; a structure
  /// may alternate between the rays' traversals to overlap their memory accesses (WideBvh does
  /// for incoherent batches). `hits` has the size of `rays`.
  virtual void intersect_batch(std::span<const Ray> rays, std::span<Hit> hits,
                               BatchOrder order) const {
    (void)order;
    for (size_t i = 0; i < rays.size(); ++i) intersect(rays[i], hits[i]);
  }
  /// out[i] = occluded(rays[i]) for every i, as intersect_batch. `out` has the size of `rays`.
  virtual void occluded_batch(std::span<const Ray> rays, std::span<uint8_t> out,
                              BatchOrder order) const {
    (void)order;
    for (size_t i = 0; i < rays.size(); ++i) out[i] = occluded(rays[i]);
  }
  /// intersect, adding to `cost` the nodes it visited and the primitives it tested (the same
  /// traversal as intersect, instantiated with counting; intersect itself counts nothing).
  virtual bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const = 0;
  /// occluded, adding to `cost` the nodes it visited and the primitives it tested (as
  /// intersect_cost; the any-hit order of the structure, stopping at the first hit found).
  virtual bool occluded_cost(const Ray& ray, TraversalCost& cost) const = 0;
  /// Statistics of the last build.
  virtual AccelStats stats() const = 0;
  /// The instruction set the structure's code was compiled for (compiled_vectors(): "AVX-512",
  /// "AVX2", "SSE2", ...): the build's target, or the level `isa=` chose when the program ran
  /// (registry.h). Inline, so each level's copy of the code reports its own.
  virtual const char* vectors() const { return compiled_vectors(); }
};

}  // namespace penumbra
