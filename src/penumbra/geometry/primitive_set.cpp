#include "penumbra/geometry/primitive_set.h"

#include <cmath>

#include "penumbra/core/error.h"

namespace penumbra {

namespace {
bool finite_box(const Bounds3& b) {
  return is_finite(b.lo) && is_finite(b.hi) && !b.empty();
}
}  // namespace

uint32_t PrimitiveSet::push(PrimKind kind, uint32_t slot, PrimOrigin origin) {
  if (kinds_.size() >= size_t(kNoPrim)) throw Error("too many primitives (more than 2^32 - 1)");
  kinds_.push_back(kind);
  slot_.push_back(slot);
  origins_.push_back(origin);
  const auto id = static_cast<uint32_t>(kinds_.size() - 1);
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
    push(PrimKind::kTriangle, slot, {shape, static_cast<uint32_t>(i)});
  }
  return first;
}

uint32_t PrimitiveSet::add_sphere(const SphereData& s, uint32_t shape) {
  spheres_.push_back(s);
  return push(PrimKind::kSphere, static_cast<uint32_t>(spheres_.size() - 1), {shape, 0});
}

uint32_t PrimitiveSet::add_quad(const QuadData& q, uint32_t shape) {
  quads_.push_back(q);
  return push(PrimKind::kQuad, static_cast<uint32_t>(quads_.size() - 1), {shape, 0});
}

Bounds3 PrimitiveSet::prim_bounds(uint32_t id) const {
  // Every defining coordinate is checked: min/max skip a NaN argument, so a box alone could
  // look finite while a vertex is NaN.
  Bounds3 b;
  bool finite = true;
  switch (kinds_[id]) {
    case PrimKind::kTriangle: {
      const Vec3* p = triangle(id);
      finite = is_finite(p[0]) && is_finite(p[1]) && is_finite(p[2]);
      b = Bounds3::of_point(p[0]);
      b.extend(p[1]);
      b.extend(p[2]);
      break;
    }
    case PrimKind::kSphere: {
      const SphereData& s = sphere(id);
      finite = is_finite(s.center) && std::isfinite(s.radius);
      b = Bounds3(s.center - Vec3(s.radius), s.center + Vec3(s.radius));
      break;
    }
    case PrimKind::kQuad: {
      const QuadData& q = quad(id);
      finite = is_finite(q.p) && is_finite(q.e1) && is_finite(q.e2);
      b = Bounds3::of_point(q.p);
      b.extend(q.p + q.e1);
      b.extend(q.p + q.e2);
      b.extend(q.p + q.e1 + q.e2);
      break;
    }
  }
  return finite && finite_box(b) ? b : Bounds3{};
}

size_t PrimitiveSet::bytes() const {
  return kinds_.capacity() * sizeof(PrimKind) + slot_.capacity() * sizeof(uint32_t) +
         origins_.capacity() * sizeof(PrimOrigin) + tri_vertices_.capacity() * sizeof(Vec3) +
         spheres_.capacity() * sizeof(SphereData) + quads_.capacity() * sizeof(QuadData);
}

}  // namespace penumbra
