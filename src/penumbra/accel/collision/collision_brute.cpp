#include "penumbra/accel/collision/collision_brute.h"

#include "penumbra/accel/collision/swept_tests.h"
#include "penumbra/accel/collision/triangle_triangle.h"

namespace penumbra::collision {

std::vector<TrianglePair> intersecting_pairs_brute(const CollisionMesh& a, const CollisionMesh& b) {
  std::vector<TrianglePair> out;
  const auto na = static_cast<uint32_t>(a.triangle_count());
  const auto nb = static_cast<uint32_t>(b.triangle_count());
  for (uint32_t i = 0; i < na; ++i) {
    if (!a.valid(i)) continue;
    for (uint32_t j = 0; j < nb; ++j)
      if (b.valid(j) && valid_triangles_intersect(a.triangle(i), b.triangle(j)))
        out.push_back({i, j});
  }
  return out;  // generated in sorted order
}

std::vector<uint32_t> touched_triangles_brute(const CollisionMesh& mesh,
                                              const MovingSphere& sphere) {
  check_query(sphere);
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < mesh.triangle_count(); ++i)
    if (mesh.valid(i) &&
        moving_sphere_touches(mesh.triangle(i), sphere.from, sphere.to, sphere.radius))
      out.push_back(i);
  return out;
}

std::vector<uint32_t> touched_triangles_brute(const CollisionMesh& mesh, const MovingBox& box) {
  check_query(box);
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < mesh.triangle_count(); ++i)
    if (mesh.valid(i) && moving_box_touches(mesh.triangle(i), box.box, box.displacement))
      out.push_back(i);
  return out;
}

}  // namespace penumbra::collision
