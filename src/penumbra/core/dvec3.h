#pragma once
/// Double-precision 3-vectors, for set-ups and references that float would leave short of digits
/// (exact predicates, spherical rectangles, test references).
#include <algorithm>
#include <cmath>
#include <limits>

#include "penumbra/core/vec.h"

namespace penumbra {

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
  /// Rounded to float.
  constexpr Vec3 to_float() const { return {float(x), float(y), float(z)}; }
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
/// Length.
inline double length(const DVec3& v) {
  return std::sqrt(dot(v, v));
}
/// The unit vector along v.
inline DVec3 normalize(const DVec3& v) {
  return v * (1.0 / length(v));
}
/// True when every coordinate is finite.
inline bool is_finite(const DVec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// The largest float not above `d` (outward rounding of a lower bound).
inline float round_down(double d) {
  const auto f = static_cast<float>(d);
  return double(f) > d ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
/// The smallest float not below `d` (outward rounding of an upper bound).
inline float round_up(double d) {
  const auto f = static_cast<float>(d);
  return double(f) < d ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}
/// Per coordinate round_down.
inline Vec3 round_down(const DVec3& v) {
  return {round_down(v.x), round_down(v.y), round_down(v.z)};
}
/// Per coordinate round_up.
inline Vec3 round_up(const DVec3& v) {
  return {round_up(v.x), round_up(v.y), round_up(v.z)};
}

}  // namespace penumbra
