#pragma once
/// Brute-force references for the collision queries: every pair of triangles, every triangle,
/// the exact test alone, no boxes. For the tests and `penumbra collide --brute`.
#include <cstdint>
#include <vector>

#include "penumbra/accel/collision/collision.h"

namespace penumbra::collision {

/// intersecting_pairs by testing all |a| x |b| pairs (sorted).
std::vector<TrianglePair> intersecting_pairs_brute(const CollisionMesh& a, const CollisionMesh& b);

/// touched_triangles (sphere) by testing every triangle (sorted).
std::vector<uint32_t> touched_triangles_brute(const CollisionMesh& mesh,
                                              const MovingSphere& sphere);

/// touched_triangles (box) by testing every triangle (sorted).
std::vector<uint32_t> touched_triangles_brute(const CollisionMesh& mesh, const MovingBox& box);

}  // namespace penumbra::collision
