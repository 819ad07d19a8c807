#include "penumbra/geometry/primitive_set.h"

#include <cmath>

#include "penumbra/core/dvec3.h"
#include "penumbra/core/error.h"

namespace penumbra {

namespace {
bool finite_box(const Bounds3& b) {
  return is_finite(b.lo) && is_finite(b.hi) && !b.empty() &&
         max_component(abs(b.lo)) <= kMaxCoordinate && max_component(abs(b.hi)) <= kMaxCoordinate;
}
}  // namespace

uint32_t PrimitiveSet::push(PrimKind kind, bool moving, uint32_t slot, PrimOrigin origin) {
  if (codes_.size() >= size_t(kNoPrim)) throw Error("too many primitives (more than 2^32 - 1)");
  codes_.push_back(uint8_t(uint8_t(kind) | (moving ? kMovingBit : 0)));
  slot_.push_back(slot);
  origins_.push_back(origin);
  moving_count_ += moving;
  const auto id = static_cast<uint32_t>(codes_.size() - 1);
  bounds_.extend(prim_bounds(id));  // empty (no change) for a non-finite primitive
  return id;
}

uint32_t PrimitiveSet::add_mesh(const TriangleMesh& mesh, const Transform& to_world,
                                uint32_t shape) {
  const uint32_t first = size();
  const size_t n = mesh.triangle_count();
  tri_vertices_.reserve(tri_vertices_.size() + 3 * n);
  for (size_t i = 0; i < n; ++i) {
    const auto slot = static_cast<uint32_t>(tri_vertices_.size() / 3);
    for (int k = 0; k < 3; ++k)
      tri_vertices_.push_back(to_world.point(mesh.positions.at(mesh.indices[3 * i + k])));
    push(PrimKind::kTriangle, false, slot, {shape, static_cast<uint32_t>(i)});
  }
  return first;
}

uint32_t PrimitiveSet::add_sphere(const SphereData& s, uint32_t shape) {
  spheres_.push_back(s);
  return push(PrimKind::kSphere, false, static_cast<uint32_t>(spheres_.size() - 1), {shape, 0});
}

uint32_t PrimitiveSet::add_quad(const QuadData& q, uint32_t shape) {
  quads_.push_back(q);
  return push(PrimKind::kQuad, false, static_cast<uint32_t>(quads_.size() - 1), {shape, 0});
}

uint32_t PrimitiveSet::add_moving_mesh(const TriangleMesh& mesh, const Transform& start,
                                       const Transform& end, uint32_t shape) {
  const uint32_t first = size();
  const size_t n = mesh.triangle_count();
  for (size_t i = 0; i < n; ++i) {
    const auto slot = static_cast<uint32_t>(tri_vertices_.size() / 3);
    Vec3 a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.positions.at(mesh.indices[3 * i + k]);
      a[k] = start.point(p), b[k] = end.point(p);
    }
    // Start vertices, then (for a moving triangle) end vertices in the next slot.
    const bool moves = !(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]);
    tri_vertices_.insert(tri_vertices_.end(), a, a + 3);
    if (moves) tri_vertices_.insert(tri_vertices_.end(), b, b + 3);
    push(PrimKind::kTriangle, moves, slot, {shape, static_cast<uint32_t>(i)});
  }
  return first;
}

uint32_t PrimitiveSet::add_moving_sphere(const SphereData& start, const SphereData& end,
                                         uint32_t shape) {
  const bool moves = !(start.center == end.center && start.radius == end.radius);
  const auto slot = static_cast<uint32_t>(spheres_.size());
  spheres_.push_back(start);
  if (moves) spheres_.push_back(end);
  return push(PrimKind::kSphere, moves, slot, {shape, 0});
}

uint32_t PrimitiveSet::add_moving_quad(const QuadData& start, const QuadData& end, uint32_t shape) {
  const bool moves = !(start.p == end.p && start.e1 == end.e1 && start.e2 == end.e2);
  const auto slot = static_cast<uint32_t>(quads_.size());
  quads_.push_back(start);
  if (moves) quads_.push_back(end);
  return push(PrimKind::kQuad, moves, slot, {shape, 0});
}

void PrimitiveSet::triangle_at(uint32_t id, float time, Vec3 out[3]) const {
  const Vec3 *a = triangle(id), *b = triangle_end(id);
  if (!moving(id)) {
    out[0] = a[0], out[1] = a[1], out[2] = a[2];
    return;
  }
  const float t = motion_time(time);
  for (int k = 0; k < 3; ++k) out[k] = motion_lerp(t, a[k], b[k]);
}

SphereData PrimitiveSet::sphere_at(uint32_t id, float time) const {
  const SphereData &a = sphere(id), &b = sphere_end(id);
  if (!moving(id)) return a;
  const float t = motion_time(time);
  return {motion_lerp(t, a.center, b.center), motion_lerp(t, a.radius, b.radius)};
}

QuadData PrimitiveSet::quad_at(uint32_t id, float time) const {
  const QuadData &a = quad(id), &b = quad_end(id);
  if (!moving(id)) return a;
  const float t = motion_time(time);
  return {motion_lerp(t, a.p, b.p), motion_lerp(t, a.e1, b.e1), motion_lerp(t, a.e2, b.e2)};
}

// Flattened: the kernels are inlined here as they are in the static switch (a call to the
// triangle test alone cost a third more per test, measured on a moving bunny).
[[gnu::flatten]] bool PrimitiveSet::intersect_moving(uint32_t id, const PreparedRay& pr,
                                                     Hit& hit) const {
  // The primitive at the ray's time, computed per test (nothing is cached between rays), then
  // the static kernels. A moving primitive's end follows its start in the per-kind array; the
  // interpolation is that of triangle_at, sphere_at and quad_at.
  const float s = motion_time(pr.ray.time);
  float t, u = 0, v = 0;
  const float tmax = tie_bound(hit, id);
  switch (kind(id)) {
    case PrimKind::kTriangle: {
      const Vec3* a = triangle(id);
      if (!intersect_triangle(pr, motion_lerp(s, a[0], a[3]), motion_lerp(s, a[1], a[4]),
                              motion_lerp(s, a[2], a[5]), pr.ray.tmin, tmax, t, u, v))
        return false;
      break;
    }
    case PrimKind::kSphere: {
      const SphereData* a = &sphere(id);
      if (!intersect_sphere(pr.ray, motion_lerp(s, a[0].center, a[1].center),
                            motion_lerp(s, a[0].radius, a[1].radius), pr.ray.tmin, tmax, t))
        return false;
      break;
    }
    case PrimKind::kQuad: {
      const QuadData* a = &quad(id);
      if (!intersect_quad(pr.ray, motion_lerp(s, a[0].p, a[1].p), motion_lerp(s, a[0].e1, a[1].e1),
                          motion_lerp(s, a[0].e2, a[1].e2), pr.ray.tmin, tmax, t, u, v))
        return false;
      break;
    }
    default:
      return false;
  }
  hit = {t, u, v, id};
  return true;
}

Bounds3 PrimitiveSet::end_bounds(uint32_t id, bool end, bool& finite) const {
  // Every defining coordinate is checked: min/max skip a NaN argument, so a box alone could
  // look finite while a vertex is NaN.
  Bounds3 b;
  switch (kind(id)) {
    case PrimKind::kTriangle: {
      const Vec3* p = end ? triangle_end(id) : triangle(id);
      finite = finite && is_finite(p[0]) && is_finite(p[1]) && is_finite(p[2]);
      b = Bounds3::of_point(p[0]);
      b.extend(p[1]);
      b.extend(p[2]);
      break;
    }
    case PrimKind::kSphere: {
      const SphereData& s = end ? sphere_end(id) : sphere(id);
      finite = finite && is_finite(s.center) && std::isfinite(s.radius);
      // Rounded outward: in float, c - r rounds to c when r is below half an ulp of c (a small
      // sphere far from the origin), and the box would miss the sphere the exact test sees.
      const DVec3 c(s.center), r(s.radius, s.radius, s.radius);
      b = Bounds3(round_down(c - r), round_up(c + r));
      break;
    }
    case PrimKind::kQuad: {
      const QuadData& q = end ? quad_end(id) : quad(id);
      finite = finite && is_finite(q.p) && is_finite(q.e1) && is_finite(q.e2);
      // Corners in double, rounded outward (float sums may round a corner inward), together
      // with the corners as float sums give them (what code that computes p + e1 + e2 in float
      // sees, a rounding or two beyond the exact corner).
      const DVec3 p(q.p), e1(q.e1), e2(q.e2);
      const DVec3 lo = min(min(p, p + e1), min(p + e2, p + e1 + e2));
      const DVec3 hi = max(max(p, p + e1), max(p + e2, p + e1 + e2));
      b = Bounds3(round_down(lo), round_up(hi));
      b.extend(q.p + q.e1);
      b.extend(q.p + q.e2);
      b.extend(q.p + q.e1 + q.e2);
      break;
    }
  }
  return b;
}

Bounds3 PrimitiveSet::prim_bounds(uint32_t id) const {
  bool finite = true;
  Bounds3 b = end_bounds(id, false, finite);
  // A moving primitive: each point moves along a segment, so the union of both ends' boxes is
  // exactly the box of everything it sweeps (also for the interpolated radius of a sphere).
  if (moving(id)) b.extend(end_bounds(id, true, finite));
  return finite && finite_box(b) ? b : Bounds3{};
}

size_t PrimitiveSet::bytes() const {
  return codes_.capacity() * sizeof(uint8_t) + slot_.capacity() * sizeof(uint32_t) +
         origins_.capacity() * sizeof(PrimOrigin) + tri_vertices_.capacity() * sizeof(Vec3) +
         spheres_.capacity() * sizeof(SphereData) + quads_.capacity() * sizeof(QuadData);
}

}  // namespace penumbra
