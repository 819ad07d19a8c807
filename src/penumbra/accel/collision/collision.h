#pragma once
/// Collision queries over the hierarchies of CollisionMesh: the intersecting triangle pairs of two
/// meshes, and the triangles that a moving sphere or a moving box touches. Boxes cull, exact
/// tests decide (triangle_triangle.h, swept_tests.h); every culling test is conservative, so the
/// answers are exactly those of the brute-force references in collision_brute.h.
#include <compare>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/accel/collision/collision_mesh.h"
#include "penumbra/accel/collision/dvec3.h"

namespace penumbra::collision {

/// An intersecting pair: a triangle of the first mesh and one of the second (input indices).
struct TrianglePair {
  uint32_t a = 0, b = 0;
  auto operator<=>(const TrianglePair&) const = default;
};

/// A sphere of radius `radius` whose centre moves along the segment from -> to.
struct MovingSphere {
  DVec3 from, to;
  double radius = 0;
};

/// The axis-aligned box `box` moved by `displacement` (it sweeps box + s * displacement, s in
/// [0, 1]).
struct MovingBox {
  DBox box;
  DVec3 displacement;
};

/// Work done by one query.
struct QueryStats {
  size_t node_tests = 0;   ///< box tests between nodes (or a node and the query volume)
  size_t exact_tests = 0;  ///< exact triangle tests (after the triangle boxes passed)
};

/// Sorted, duplicate-free pairs of intersecting (closed) triangles of `a` and `b`, by a
/// simultaneous descent of the two hierarchies.
std::vector<TrianglePair> intersecting_pairs(const CollisionMesh& a, const CollisionMesh& b,
                                             QueryStats* stats = nullptr);

/// Sorted ids of the triangles of `mesh` that the moving sphere touches; throws Error for a
/// non-finite or negative input.
std::vector<uint32_t> touched_triangles(const CollisionMesh& mesh, const MovingSphere& sphere,
                                        QueryStats* stats = nullptr);

/// Sorted ids of the triangles of `mesh` that the moving box touches; throws Error for a
/// non-finite input or lo > hi.
std::vector<uint32_t> touched_triangles(const CollisionMesh& mesh, const MovingBox& box,
                                        QueryStats* stats = nullptr);

/// Throws Error unless the sphere is finite with radius >= 0.
void check_query(const MovingSphere& sphere);
/// Throws Error unless the box is finite with lo <= hi and the displacement finite.
void check_query(const MovingBox& box);

}  // namespace penumbra::collision
