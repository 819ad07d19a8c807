#pragma once
/// What a builder sees of a primitive: its box and its id (Embree's PrimRef; builders know
/// nothing of meshes, only boxes and centroids).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "penumbra/core/array_allocator.h"
#include "penumbra/core/bounds.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// A primitive's box and id in 32 bytes; the centroid is implied by the box.
struct alignas(32) PrimRef {
  Vec3 lo;
  uint32_t id;
  Vec3 hi;
  uint32_t pad;

  /// Twice the box centre (the builders bin on lo + hi to save a multiplication).
  Vec3 centroid2() const { return lo + hi; }
  /// The box.
  Bounds3 bounds() const { return {lo, hi}; }
};
static_assert(sizeof(PrimRef) == 32);

/// The reference of primitive `id` with box `box`, zero coordinates made +0 (x + 0 turns -0
/// into +0 and leaves every other value unchanged), so that min/max reductions over
/// references do not depend on the order of combination.
inline PrimRef make_prim_ref(const Bounds3& box, uint32_t id) {
  return {box.lo + Vec3(0.0f), id, box.hi + Vec3(0.0f), 0};
}

/// An array of references whose sizing writes nothing (the builders fill what they read).
using PrimRefArray = std::vector<PrimRef, NoInitArrayAllocator<PrimRef>>;

/// Primitive references of a set, with the totals a top-down builder starts from.
struct PrimRefs {
  PrimRefArray refs;        ///< one per finite primitive, id order
  Bounds3 bounds;           ///< union of the boxes
  Bounds3 centroid_bounds;  ///< bounds of centroid2() over all refs
};

/// True for a primitive that no ray can hit though its box is not empty: a static triangle with
/// two identical vertices (repeated_vertex in geometry/triangle.h). Structures leave it out.
bool never_hit(const PrimitiveSet& prims, uint32_t id);

/// References to every primitive of `prims` with a non-empty box that never_hit does not rule
/// out (others can never be hit and are skipped). Zero coordinates are normalised to +0 so that
/// min/max reductions do not depend on the order of combination (the build is then identical
/// for every thread count). Parallel.
/// `spare` reserves room for that many more references (spatial splits add them in place).
PrimRefs make_prim_refs(const PrimitiveSet& prims, size_t spare = 0);

/// The largest extent along an axis of a reference's box: what structures of cells scale their
/// cull slack by (cull_slack in geometry/hit.h).
inline float max_prim_extent(const PrimRefs& refs) {
  float m = 0;
  for (const PrimRef& r : refs.refs) m = std::max(m, max_component(r.bounds().diagonal()));
  return m;
}

}  // namespace penumbra
