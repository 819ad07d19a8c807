#pragma once
/// Generated scenes and ray sets for the accelerator tests (no files are read).
#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/core/ray.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra::test {

/// A named primitive set.
struct TestScene {
  std::string name;
  PrimitiveSet prims;
};

/// `n` random triangles of varied size in the unit cube.
TestScene random_soup(int n, uint64_t seed);
/// An nx x ny grid of unit squares in the plane z = 0 (two triangles each, integer vertices,
/// shared edges), plus a second grid at z = 1 offset by half a cell.
TestScene coplanar_grid(int nx, int ny);
/// A closed room [0,10]^3 with `boxes` axis-aligned boxes inside (all triangles, axis-aligned).
TestScene room_with_boxes(int boxes, uint64_t seed);
/// Needle-thin, tiny and very large triangles mixed.
TestScene thin_and_large(uint64_t seed);
/// Spheres, parallelograms and triangles together (not all triangles).
TestScene mixed_shapes(uint64_t seed);
/// Ordinary triangles mixed with zero-area, NaN-vertex and infinite-vertex triangles.
TestScene degenerate_triangles(uint64_t seed);
/// A torus tessellated into 2 * rings * sides triangles (a stand-in for a scanned mesh).
TestScene torus(int rings, int sides);

/// A mixed ray set over `prims`: random origins and directions, origins on surfaces, directions
/// with zero components and axis-parallel rays with origins on vertex coordinates (so they run
/// along box and triangle planes). tmin = 0, tmax = infinity.
std::vector<Ray> mixed_rays(const PrimitiveSet& prims, size_t n, uint64_t seed);

/// A point on primitive `id` (random barycentric / surface coordinates from u1, u2).
Vec3 point_on(const PrimitiveSet& prims, uint32_t id, float u1, float u2);

}  // namespace penumbra::test
