#pragma once
/// Double-precision triangles and boxes for the collision queries (points: core/dvec3.h). Mesh
/// vertices are floats; the queries take them (after an optional pose) to double so that the exact predicates and the
/// distance computations see one set of coordinates, whatever path reaches a triangle.
#include <array>
#include <cmath>

#include "penumbra/core/dvec3.h"

namespace penumbra::collision {

using penumbra::DVec3;

/// A triangle by its three vertices.
struct DTriangle {
  std::array<DVec3, 3> v;
  constexpr const DVec3& operator[](int i) const { return v[i]; }
  constexpr DVec3& operator[](int i) { return v[i]; }
};

/// An axis-aligned box of double [lo, hi].
struct DBox {
  DVec3 lo, hi;
};

}  // namespace penumbra::collision
