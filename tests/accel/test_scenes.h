#pragma once
/// Generated scenes and ray sets for the accelerator tests (no files are read).
#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
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
/// A closed room [0,10]^3 with `boxes` axis-aligned boxes inside (all triangles, axis-aligned),
/// moved by `offset` (by a translation: an offset of integers keeps every vertex exact).
TestScene room_with_boxes(int boxes, uint64_t seed, Vec3 offset = Vec3(0.0f));
/// Needle-thin, tiny and very large triangles mixed.
TestScene thin_and_large(uint64_t seed);
/// Spheres, parallelograms and triangles together (not all triangles).
TestScene mixed_shapes(uint64_t seed);
/// Coincident surfaces: a room with boxes and a soup of triangles, each triangle two or three
/// times (exact copies, and copies with their vertices rotated, whose t differs by rounding),
/// added in a shuffled order so that a copy's id is as often below as above the original's.
/// `shapes` adds spheres and parallelograms, each twice. Every ray that hits meets a tie.
TestScene coincident_surfaces(uint64_t seed, bool shapes);
/// Ordinary triangles mixed with zero-area, NaN-vertex and infinite-vertex triangles.
TestScene degenerate_triangles(uint64_t seed);
/// True for a primitive a structure must reference: its box is not empty and never_hit
/// (accel/build/prim_ref.h) does not rule it out.
bool referenced_by_structures(const PrimitiveSet& prims, uint32_t id);
/// `scene` with every point p mapped to p * scale + offset (sphere radii and edges scaled),
/// named after the map: for the differential tests at extreme magnitudes.
TestScene scaled(const TestScene& scene, float scale, Vec3 offset);
/// random_soup(500, seed) plus a few triangles with vertices near the float range (about
/// +-3e38, beyond kMaxCoordinate: never hit), and a triangle and a sphere reaching
/// kMaxCoordinate (hit like any other). Rays for it come from random_soup(500, seed).
TestScene float_range_extent(uint64_t seed);
/// A torus tessellated into 2 * rings * sides triangles (a stand-in for a scanned mesh).
TestScene torus(int rings, int sides);

/// `n` random triangles as in random_soup, four in five moving (translated by up to a tenth of
/// the cube, turned by up to 40 degrees and scaled between time 0 and time 1), the rest static.
TestScene moving_soup(int n, uint64_t seed);
/// Moving spheres (some growing), parallelograms and triangles, a few of each static.
TestScene moving_shapes(uint64_t seed);
/// A static room with boxes (as room_with_boxes) crossed by moving triangles, spheres and quads.
TestScene static_and_moving(uint64_t seed);
/// Gives every ray a time: mostly uniform in [0, 1], some exactly 0 or 1, some outside [0, 1]
/// (where primitives stay at their ends).
void set_random_times(std::vector<Ray>& rays, uint64_t seed);

/// A mixed ray set over `prims`: random origins and directions, origins on surfaces, directions
/// with zero components and axis-parallel rays with origins on vertex coordinates (so they run
/// along box and triangle planes). tmin = 0, tmax = infinity.
std::vector<Ray> mixed_rays(const PrimitiveSet& prims, size_t n, uint64_t seed);

/// `n` large triangles across the unit cube and `small` little ones (about 0.01 across), from
/// `seed`. Without `slivers` all three vertices of a large one lie anywhere (large, diagonal
/// triangles: pre-splitting's case); with it two lie anywhere and the third near the first
/// (long, thin ones: the case of spatial splits).
TestScene large_triangles(int n, int small, uint64_t seed, bool slivers = false);

/// Traces `rays` through `a` and `b`, adding the work of each to `cost_a` and `cost_b`, and
/// checks (gtest) that both find a hit for the same rays at the same distance.
void trace_both(const Accelerator& a, const Accelerator& b, const std::vector<Ray>& rays,
                TraversalCost& cost_a, TraversalCost& cost_b);

/// A structure's figure `key` from AccelStats::extra (a test failure when it reports none).
double extra_stat(const Accelerator& acc, const std::string& key);

/// Registered structures other than the reference, `brute`.
std::vector<std::string> structure_names();
/// A structure's name made a valid test name (every character but letters and digits as '_'),
/// for INSTANTIATE_TEST_SUITE_P over the registry.
std::string structure_test_name(const std::string& name);

/// A point on primitive `id` (random barycentric / surface coordinates from u1, u2), at time 0
/// for a moving primitive.
Vec3 point_on(const PrimitiveSet& prims, uint32_t id, float u1, float u2);

}  // namespace penumbra::test
