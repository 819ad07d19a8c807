#pragma once
/// Small fixed-size vectors: Vec2 and Vec3 of float, used for points, directions and normals alike.
/// Points and directions transform differently; Transform names the operation (point, vector, normal).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace penumbra {

/// A 2D vector of float.
struct Vec2 {
  float x = 0, y = 0;
  constexpr Vec2() = default;
  constexpr Vec2(float x_, float y_) : x(x_), y(y_) {}
  constexpr float operator[](int i) const { return i == 0 ? x : y; }
  constexpr Vec2 operator+(Vec2 b) const { return {x + b.x, y + b.y}; }
  constexpr Vec2 operator-(Vec2 b) const { return {x - b.x, y - b.y}; }
  constexpr Vec2 operator*(float s) const { return {x * s, y * s}; }
  constexpr bool operator==(const Vec2&) const = default;
};

/// A 3D vector of float (point, direction or normal).
struct Vec3 {
  float x = 0, y = 0, z = 0;
  constexpr Vec3() = default;
  constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3(float s) : x(s), y(s), z(s) {}
  /// Component i (0, 1 or 2). At run time an indexed load, not a chain of selects: GCC compiled
  /// the selects to two branches, and an axis chosen per ray (the watertight test's permutation,
  /// a split axis) is as unpredictable as the ray (they cost an incoherent ray about two
  /// mispredictions in the traversal's setup).
  constexpr float operator[](int i) const {
    if (std::is_constant_evaluated()) return i == 0 ? x : (i == 1 ? y : z);
    float v;
    __builtin_memcpy(&v, reinterpret_cast<const char*>(this) + sizeof(float) * size_t(i), sizeof v);
    return v;
  }
  constexpr float& operator[](int i) {
    if (std::is_constant_evaluated()) return i == 0 ? x : (i == 1 ? y : z);
    return *reinterpret_cast<float*>(reinterpret_cast<char*>(this) + sizeof(float) * size_t(i));
  }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator+(Vec3 b) const { return {x + b.x, y + b.y, z + b.z}; }
  constexpr Vec3 operator-(Vec3 b) const { return {x - b.x, y - b.y, z - b.z}; }
  constexpr Vec3 operator*(Vec3 b) const { return {x * b.x, y * b.y, z * b.z}; }
  constexpr Vec3 operator/(Vec3 b) const { return {x / b.x, y / b.y, z / b.z}; }
  constexpr Vec3 operator*(float s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(float s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3& operator+=(Vec3 b) { return *this = *this + b; }
  constexpr Vec3& operator-=(Vec3 b) { return *this = *this - b; }
  constexpr Vec3& operator*=(float s) { return *this = *this * s; }
  constexpr bool operator==(const Vec3&) const = default;
};
static_assert(std::is_standard_layout_v<Vec3> && sizeof(Vec3) == 3 * sizeof(float),
              "Vec3::operator[] reads the components as consecutive floats");

constexpr Vec3 operator*(float s, Vec3 v) { return v * s; }
constexpr float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Squared lengths in this range have finite, normal squares on the way: the fast paths.
inline constexpr float kSafeLengthSqLo = 1e-30f, kSafeLengthSqHi = 1e30f;
/// |v| for every finite v. The squares of components beyond about 1.8e19 overflow and those
/// below about 1e-19 underflow, so such vectors are scaled by their largest component first
/// (a cross product of two edges of 1e10 is 1e20: its plain length would be infinite).
inline float length(Vec3 v) {
  const float l2 = dot(v, v);
  if (l2 > kSafeLengthSqLo && l2 < kSafeLengthSqHi) [[likely]]
    return std::sqrt(l2);
  const float m = std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
  if (!(m > 0.0f) || !std::isfinite(m)) return std::sqrt(l2);  // zero, infinite or NaN
  const Vec3 u = v / m;
  return m * std::sqrt(dot(u, u));
}
/// The unit vector along v, for every finite non-zero v (scaled first, as in length).
inline Vec3 normalize(Vec3 v) {
  const float l2 = dot(v, v);
  if (l2 > kSafeLengthSqLo && l2 < kSafeLengthSqHi) [[likely]]
    return v / std::sqrt(l2);
  const float m = std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
  if (!(m > 0.0f) || !std::isfinite(m)) return v / std::sqrt(l2);  // zero, infinite or NaN
  const Vec3 u = v / m;
  return u / std::sqrt(dot(u, u));
}
constexpr Vec3 min(Vec3 a, Vec3 b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
constexpr Vec3 max(Vec3 a, Vec3 b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline Vec3 abs(Vec3 v) { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }
constexpr float max_component(Vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }
/// Index (0, 1, 2) of the largest component.
constexpr int max_dimension(Vec3 v) { return v.x > v.y ? (v.x > v.z ? 0 : 2) : (v.y > v.z ? 1 : 2); }
inline bool is_finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
/// Normal flipped, if needed, to lie in the hemisphere of `v`.
constexpr Vec3 face_forward(Vec3 n, Vec3 v) { return dot(n, v) < 0.f ? -n : n; }

/// Builds an orthonormal basis (t, b) around the unit vector n (Duff et al. 2017, "Building an
/// Orthonormal Basis, Revisited", JCGT 6(1)).
inline void orthonormal_basis(Vec3 n, Vec3& t, Vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

}  // namespace penumbra
