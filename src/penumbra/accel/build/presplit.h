#pragma once
/// Pre-splitting of large triangles before a BVH build (bvh:presplit=F): a triangle whose box is
/// much larger than the triangle itself (long, thin or diagonal triangles of terrains, CAD and
/// architecture) gets several references, each bounding the part of the triangle on one side of
/// a split plane, so the builder can place the parts in different subtrees. The idea and the
/// budget are Karras & Aila's ("Fast Parallel Construction of High-Quality Bounding Volume
/// Hierarchies", HPG 2013, section 4; Ernst & Greiner 2007, "Early Split Clipping", before):
/// a fixed budget of extra references, F times the triangle count, shared among the triangles
/// by a priority, and splits at the planes of a power-of-two grid over the scene, which are the
/// planes the builder's own splits tend to use.
///
/// Ours: the priority of a triangle is the cube root of its box's wasted area (surface area
/// minus twice the triangle's area, the least a box of it can have), so the budget spreads over
/// many large triangles rather than going to a few huge ones; a triangle of k + 1 pieces is
/// split at the coarsest grid plane crossing its box (the longest axis on a tie), the parts'
/// boxes clipped exactly (kd_clip.h, rounded outward), and the pieces shared between the two
/// sides in proportion to their boxes' surface areas.
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// Adds at most `budget` × refs.size() references to `refs` (one per triangle of the all-triangle
/// set `prims` on entry), by splitting the triangles of largest wasted area; the references of a
/// triangle are contiguous and in the order of its triangle. The union of a triangle's boxes
/// holds the whole triangle, so every hit is still found, but a leaf may hold one triangle
/// twice. Deterministic: the same result at every thread count. `budget` in [0, 4].
void presplit_refs(const PrimitiveSet& prims, PrimRefs& refs, double budget);

}  // namespace penumbra
