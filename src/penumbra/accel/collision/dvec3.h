#pragma once
/// Double-precision points and triangles for the collision queries. Mesh vertices are floats;
/// the queries take them (after an optional pose) to double so that the exact predicates and the
/// distance computations see one set of coordinates, whatever path reaches a triangle.
#include <array>
#include <cmath>

#include "penumbra/core/vec.h"

namespace penumbra::collision {

/// A 3D vector of double.
struct DVec3 {
  double x = 0, y = 0, z = 0;
  constexpr DVec3() = default;
  constexpr DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  /// Widening from float (exact).
  constexpr explicit DVec3(Vec3 v) : x(v.x), y(v.y), z(v.z) {}
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr DVec3 operator-() const { return {-x, -y, -z}; }
  constexpr DVec3 operator+(const DVec3& b) const { return {x + b.x, y + b.y, z + b.z}; }
  constexpr DVec3 operator-(const DVec3& b) const { return {x - b.x, y - b.y, z - b.z}; }
  constexpr DVec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr bool operator==(const DVec3&) const = default;
};

constexpr DVec3 operator*(double s, const DVec3& v) {
  return v * s;
}
constexpr double dot(const DVec3& a, const DVec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr DVec3 cross(const DVec3& a, const DVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr DVec3 min(const DVec3& a, const DVec3& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
constexpr DVec3 max(const DVec3& a, const DVec3& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
/// Squared length.
constexpr double length_sq(const DVec3& v) {
  return dot(v, v);
}
/// True when every coordinate is finite.
inline bool is_finite(const DVec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

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
