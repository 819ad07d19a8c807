#pragma once
/// All primitives of a scene in world space, addressed by a dense primitive id. Acceleration
/// structures see only boxes, centroids and the per-primitive intersection below; they know
/// nothing of meshes, materials or lights.
#include <cstdint>
#include <vector>

#include "penumbra/core/bounds.h"
#include "penumbra/core/transform.h"
#include "penumbra/geometry/hit.h"
#include "penumbra/geometry/prepared_ray.h"
#include "penumbra/geometry/quad.h"
#include "penumbra/geometry/sphere.h"
#include "penumbra/geometry/triangle.h"
#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {

/// The closed set of primitive kinds; intersection switches over it (no virtual call).
enum class PrimKind : uint8_t { kTriangle, kSphere, kQuad };

/// A sphere in world space.
struct SphereData {
  Vec3 center;
  float radius;
};

/// A parallelogram p + u e1 + v e2, u, v in [0, 1], in world space.
struct QuadData {
  Vec3 p, e1, e2;
};

/// Where a primitive came from: the shape (scene object) and its index within that shape.
struct PrimOrigin {
  uint32_t shape;
  uint32_t local;
};

/// World-space primitives with dense ids 0..size()-1, in the order they were added.
class PrimitiveSet {
 public:
  /// Appends the triangles of `mesh` transformed to world space; returns the first new id.
  uint32_t add_mesh(const TriangleMesh& mesh, const Transform& to_world, uint32_t shape);
  /// Appends a sphere; returns its id.
  uint32_t add_sphere(const SphereData& s, uint32_t shape);
  /// Appends a parallelogram; returns its id.
  uint32_t add_quad(const QuadData& q, uint32_t shape);

  /// Number of primitives.
  uint32_t size() const { return static_cast<uint32_t>(kinds_.size()); }
  PrimKind kind(uint32_t id) const { return kinds_[id]; }
  const PrimOrigin& origin(uint32_t id) const { return origins_[id]; }
  /// True when every primitive is a triangle (accelerators may specialise for this).
  bool all_triangles() const { return spheres_.empty() && quads_.empty(); }
  /// Vertices of triangle primitive `id` (requires kind(id) == kTriangle).
  const Vec3* triangle(uint32_t id) const { return &tri_vertices_[3 * size_t(slot_[id])]; }
  const SphereData& sphere(uint32_t id) const { return spheres_[slot_[id]]; }
  const QuadData& quad(uint32_t id) const { return quads_[slot_[id]]; }

  /// World bounds of primitive `id`; empty for a primitive with non-finite coordinates, which
  /// builders must skip (such a primitive can never be hit).
  Bounds3 prim_bounds(uint32_t id) const;
  /// Bounds of all primitives with finite bounds.
  const Bounds3& bounds() const { return bounds_; }

  /// Tests primitive `id` on (ray.tmin, hit.t); on a closer hit updates `hit` and returns true.
  bool intersect(uint32_t id, const PreparedRay& pr, Hit& hit) const {
    float t, u = 0, v = 0;
    switch (kinds_[id]) {
      case PrimKind::kTriangle: {
        const Vec3* p = triangle(id);
        if (!intersect_triangle(pr, p[0], p[1], p[2], pr.ray.tmin, hit.t, t, u, v)) return false;
        break;
      }
      case PrimKind::kSphere: {
        const SphereData& s = sphere(id);
        if (!intersect_sphere(pr.ray, s.center, s.radius, pr.ray.tmin, hit.t, t)) return false;
        break;
      }
      case PrimKind::kQuad: {
        const QuadData& q = quad(id);
        if (!intersect_quad(pr.ray, q.p, q.e1, q.e2, pr.ray.tmin, hit.t, t, u, v)) return false;
        break;
      }
      default:
        return false;
    }
    hit = {t, u, v, id};
    return true;
  }

  /// True when primitive `id` blocks `pr` on (ray.tmin, ray.tmax).
  bool occludes(uint32_t id, const PreparedRay& pr) const {
    Hit h;
    h.t = pr.ray.tmax;
    return intersect(id, pr, h);
  }

  /// Bytes held by the primitive data (for statistics).
  size_t bytes() const;

 private:
  uint32_t push(PrimKind kind, uint32_t slot, PrimOrigin origin);

  std::vector<PrimKind> kinds_;
  std::vector<uint32_t> slot_;  ///< index into the per-kind array
  std::vector<PrimOrigin> origins_;
  std::vector<Vec3> tri_vertices_;  ///< three per triangle
  std::vector<SphereData> spheres_;
  std::vector<QuadData> quads_;
  Bounds3 bounds_;
};

}  // namespace penumbra
