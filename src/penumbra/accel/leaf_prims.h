#pragma once
/// The primitives of a BVH in leaf order, shared by the BVH layouts: primitive ids, and for
/// triangle-only sets the vertices copied into leaf order, so that a leaf's triangles are
/// contiguous in memory.
#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/core/array_allocator.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/traversal_cost.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// Primitive ids (and triangle vertices) in leaf order.
class LeafPrims {
 public:
  /// Fills from references in leaf order (parallel); copies vertices when all are triangles.
  void build(const PrimitiveSet& prims, std::span<const PrimRef> refs);
  /// True when the vertices were copied (every primitive is a triangle).
  bool triangles() const { return !tris_.empty(); }
  /// The copied vertices, three per leaf slot (empty unless triangles()).
  const Vec3* vertices() const { return tris_.data(); }
  /// Primitive id of each leaf slot.
  std::span<const uint32_t> ids() const { return {ids_.data(), ids_.size()}; }
  /// Memory held.
  size_t bytes() const {
    return ids_.capacity() * sizeof(uint32_t) + tris_.capacity() * sizeof(Vec3);
  }

  /// Tests the `count` primitives from leaf slot `first` on (tmin, hit.t), updating `hit`.
  /// kTriangles: use the copied vertices (requires triangles()); otherwise PrimitiveSet's test.
  /// kAnyHit: return at the first hit. Returns true when anything was hit. `cost` counts the
  /// primitives tested.
  template <bool kAnyHit, bool kTriangles, class Cost = NoCost>
  bool intersect(const PrimitiveSet& prims, const PreparedRay& pr, uint32_t first, uint32_t count,
                 Hit& hit, Cost cost = {}) const {
    bool found = false;
    for (uint32_t i = first; i < first + count; ++i) {
      cost.prims(1);
      bool h;
      if constexpr (kTriangles) {
        const Vec3* v = &tris_[3 * size_t(i)];
        float t, u, w;
        h = intersect_triangle(pr, v[0], v[1], v[2], pr.ray.tmin, tie_bound(hit, ids_[i]), t, u, w);
        if (h) hit = {t, u, w, ids_[i]};
      } else {
        h = prims.intersect(ids_[i], pr, hit);
      }
      if (h) {
        if constexpr (kAnyHit) return true;
        found = true;
      }
    }
    return found;
  }

 private:
  std::vector<uint32_t, ArrayAllocator<uint32_t>> ids_;
  std::vector<Vec3, ArrayAllocator<Vec3>> tris_;  ///< three vertices per leaf slot, or empty
};

}  // namespace penumbra
