#pragma once
/// All primitives of a scene in world space, addressed by a dense primitive id. Acceleration
/// structures see only boxes, centroids and the per-primitive intersection below; they know
/// nothing of meshes, materials or lights.
///
/// Motion blur: a primitive may move linearly between a start geometry (time 0) and an end
/// geometry (time 1): vertices, a sphere's centre and radius, a parallelogram's origin and edges
/// are interpolated, (1 - t) a + t b, with t = the ray's time clamped to [0, 1]. Every point of a
/// moving primitive then traces a segment, so its bounds over the whole interval are exactly the
/// union of its bounds at both ends (prim_bounds). A static primitive takes the same code path
/// as before motion existed; moving ones are tested out of line.
#include <cstdint>
#include <vector>

#include "penumbra/core/array_allocator.h"
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

/// The time at which moving primitives are evaluated for a ray of time `time`: clamped to the
/// key interval [0, 1] (a NaN time counts as 0).
inline float motion_time(float time) {
  return time > 0.0f ? (time < 1.0f ? time : 1.0f) : 0.0f;
}

/// (1 - t) a + t b for t in [0, 1], kept within [min(a, b), max(a, b)]: rounding could step an
/// ulp outside the segment, and so outside the swept bounds. Exactly a at t = 0, b at t = 1, and
/// a when a = b.
inline float motion_lerp(float t, float a, float b) {
  const float r = a * (1.0f - t) + b * t;
  const float lo = a < b ? a : b, hi = a < b ? b : a;
  return r < lo ? lo : (r > hi ? hi : r);
}
/// motion_lerp per component.
inline Vec3 motion_lerp(float t, Vec3 a, Vec3 b) {
  return {motion_lerp(t, a.x, b.x), motion_lerp(t, a.y, b.y), motion_lerp(t, a.z, b.z)};
}

/// Where a primitive came from: the shape (scene object) and its index within that shape.
struct PrimOrigin {
  uint32_t shape;
  uint32_t local;
};

/// The largest coordinate magnitude a primitive may have (its box, so also a sphere's centre
/// plus radius and a parallelogram's far corner). The ray-primitive tests form products of
/// three coordinates relative to the ray origin (the watertight test's scaled t, the
/// parallelogram's), which stay finite in float for distances up to 2e12 (8e36 < 3.4e38); boxes,
/// extents and surface areas then stay finite too. A primitive beyond it is treated like one
/// with a NaN vertex: its bounds are empty and no structure (brute force included) ever hits
/// it; the renderer's World refuses it at load, naming it.
inline constexpr float kMaxCoordinate = 1e12f;
/// The smallest scene extent (bounding-box diagonal) the renderer accepts: below it the same
/// products of three coordinates leave float's normal range and hits are lost (a scene of
/// extent 1e-20 renders black). World refuses a smaller non-empty scene at load.
inline constexpr float kMinSceneExtent = 1e-10f;

/// World-space primitives with dense ids 0..size()-1, in the order they were added.
class PrimitiveSet {
 public:
  /// Appends the triangles of `mesh` transformed to world space; returns the first new id.
  uint32_t add_mesh(const TriangleMesh& mesh, const Transform& to_world, uint32_t shape);
  /// Appends a sphere; returns its id.
  uint32_t add_sphere(const SphereData& s, uint32_t shape);
  /// Appends a parallelogram; returns its id.
  uint32_t add_quad(const QuadData& q, uint32_t shape);
  /// Appends the triangles of `mesh` moving from `start` (time 0) to `end` (time 1); a triangle
  /// whose vertices end where they start is added as a static one. Returns the first new id.
  uint32_t add_moving_mesh(const TriangleMesh& mesh, const Transform& start, const Transform& end,
                           uint32_t shape);
  /// Appends a sphere moving from `start` to `end` (static when they are equal); returns its id.
  uint32_t add_moving_sphere(const SphereData& start, const SphereData& end, uint32_t shape);
  /// Appends a parallelogram moving from `start` to `end` (static when equal); returns its id.
  uint32_t add_moving_quad(const QuadData& start, const QuadData& end, uint32_t shape);

  /// Number of primitives.
  uint32_t size() const { return static_cast<uint32_t>(codes_.size()); }
  /// The primitive's kind, moving or not.
  PrimKind kind(uint32_t id) const { return PrimKind(codes_[id] & ~kMovingBit); }
  const PrimOrigin& origin(uint32_t id) const { return origins_[id]; }
  /// True when primitive `id` moves (its end geometry differs from its start).
  bool moving(uint32_t id) const { return (codes_[id] & kMovingBit) != 0; }
  /// True when any primitive moves.
  bool has_motion() const { return moving_count_ != 0; }
  /// Number of moving primitives.
  uint32_t moving_count() const { return moving_count_; }
  /// True when every primitive is a static triangle: accelerators may then copy the vertices of
  /// triangle(id) into their leaves. Any moving primitive makes this false, so that they go
  /// through intersect(), which interpolates.
  bool all_triangles() const { return spheres_.empty() && quads_.empty() && moving_count_ == 0; }
  /// Vertices of triangle primitive `id` (requires kind(id) == kTriangle); for a moving one, its
  /// vertices at time 0.
  const Vec3* triangle(uint32_t id) const { return &tri_vertices_[3 * size_t(slot_[id])]; }
  /// Sphere `id` (at time 0 when it moves).
  const SphereData& sphere(uint32_t id) const { return spheres_[slot_[id]]; }
  /// Parallelogram `id` (at time 0 when it moves).
  const QuadData& quad(uint32_t id) const { return quads_[slot_[id]]; }
  /// Vertices of triangle `id` at time 1 (those of triangle(id) when it is static).
  const Vec3* triangle_end(uint32_t id) const { return triangle(id) + (moving(id) ? 3 : 0); }
  /// Sphere `id` at time 1 (sphere(id) when static).
  const SphereData& sphere_end(uint32_t id) const { return spheres_[slot_[id] + moving(id)]; }
  /// Parallelogram `id` at time 1 (quad(id) when static).
  const QuadData& quad_end(uint32_t id) const { return quads_[slot_[id] + moving(id)]; }
  /// Vertices of triangle `id` at ray time `time` (see motion_time).
  void triangle_at(uint32_t id, float time, Vec3 out[3]) const;
  /// Sphere `id` at ray time `time`.
  SphereData sphere_at(uint32_t id, float time) const;
  /// Parallelogram `id` at ray time `time`.
  QuadData quad_at(uint32_t id, float time) const;

  /// World bounds of primitive `id` (for a moving one: over the whole interval, the union of its
  /// bounds at both ends); empty for a primitive with non-finite coordinates or coordinates
  /// beyond kMaxCoordinate, which builders must skip (such a primitive can never be hit).
  Bounds3 prim_bounds(uint32_t id) const;
  /// Bounds of all primitives with finite bounds.
  const Bounds3& bounds() const { return bounds_; }

  /// Tests primitive `id` on (ray.tmin, hit.t) at the ray's time; on a closer hit updates `hit`
  /// and returns true. At the very t of `hit`, the lower primitive id is the closer (tie_bound).
  bool intersect(uint32_t id, const PreparedRay& pr, Hit& hit) const {
    float t, u = 0, v = 0;
    const float tmax = tie_bound(hit, id);
    switch (PrimKind(codes_[id])) {  // a moving primitive's code matches no case
      case PrimKind::kTriangle: {
        const Vec3* p = triangle(id);
        if (!intersect_triangle(pr, p[0], p[1], p[2], pr.ray.tmin, tmax, t, u, v)) return false;
        break;
      }
      case PrimKind::kSphere: {
        const SphereData& s = sphere(id);
        if (!intersect_sphere(pr.ray, s.center, s.radius, pr.ray.tmin, tmax, t)) return false;
        break;
      }
      case PrimKind::kQuad: {
        const QuadData& q = quad(id);
        if (!intersect_quad(pr.ray, q.p, q.e1, q.e2, pr.ray.tmin, tmax, t, u, v)) return false;
        break;
      }
      default:  // out of line: static scenes keep the small inlined switch
        return intersect_moving(id, pr, hit);
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
  /// Marks a moving primitive in codes_; its end geometry follows its start in the per-kind array.
  static constexpr uint8_t kMovingBit = 4;

  uint32_t push(PrimKind kind, bool moving, uint32_t slot, PrimOrigin origin);
  /// intersect() for a moving primitive: the primitive at the ray's time.
  bool intersect_moving(uint32_t id, const PreparedRay& pr, Hit& hit) const;
  /// Bounds of the primitive's geometry at one end (`end` false: time 0); `finite` is cleared
  /// when a defining coordinate is not finite.
  Bounds3 end_bounds(uint32_t id, bool end, bool& finite) const;

  // In huge pages when large (ArrayAllocator): builds and renders read these arrays at random,
  // and on the virtual machines measured a 36 MiB triangle array in ordinary pages took 40 ms
  // to read again after other memory traffic, 1 ms in huge pages.
  template <class T>
  using Array = std::vector<T, ArrayAllocator<T>>;
  Array<uint8_t> codes_;  ///< PrimKind, plus kMovingBit for a moving primitive
  Array<uint32_t> slot_;  ///< index into the per-kind array
  Array<PrimOrigin> origins_;
  Array<Vec3> tri_vertices_;  ///< three per triangle
  Array<SphereData> spheres_;
  Array<QuadData> quads_;
  uint32_t moving_count_ = 0;
  Bounds3 bounds_;
};

}  // namespace penumbra
