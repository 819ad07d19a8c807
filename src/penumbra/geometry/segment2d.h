#pragma once
/// The plane geometry of the 2D laboratory, in double precision: points, boxes, oriented lines,
/// segments, rays, the segment–ray intersection and the tolerance-based side predicates.
///
/// core's Vec2 is float (image plane samples); the laboratory needs double so that a line through
/// two input points and the fragments a line cuts off stay within a few ulps of the input.
#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra {

/// A 2D point or direction in double precision.
struct Vec2d {
  double x = 0, y = 0;
  constexpr Vec2d() = default;
  constexpr Vec2d(double x_, double y_) : x(x_), y(y_) {}
  constexpr Vec2d operator+(Vec2d b) const { return {x + b.x, y + b.y}; }
  constexpr Vec2d operator-(Vec2d b) const { return {x - b.x, y - b.y}; }
  constexpr Vec2d operator*(double s) const { return {x * s, y * s}; }
  constexpr bool operator==(const Vec2d&) const = default;
};

/// Dot product.
constexpr double dot(Vec2d a, Vec2d b) {
  return a.x * b.x + a.y * b.y;
}
/// The z component of the 3D cross product: positive when b is counter-clockwise of a.
constexpr double cross(Vec2d a, Vec2d b) {
  return a.x * b.y - a.y * b.x;
}
/// Euclidean length.
inline double length(Vec2d v) {
  return std::hypot(v.x, v.y);
}
/// The point at parameter t of a→b; exactly a at t = 0 and exactly b at t = 1 (std::lerp is exact
/// at both ends, so fragments of a segment reproduce its endpoints bit for bit).
inline Vec2d lerp(Vec2d a, Vec2d b, double t) {
  return {std::lerp(a.x, b.x, t), std::lerp(a.y, b.y, t)};
}

/// An axis-aligned box [lo, hi]; empty when lo > hi.
struct Box2d {
  Vec2d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2d hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  /// Grows the box to hold p.
  void extend(Vec2d p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
  }
  /// True when the box holds no point.
  bool empty() const { return lo.x > hi.x || lo.y > hi.y; }
  /// Width and height.
  Vec2d extent() const { return hi - lo; }
};

/// A line {p : a x + b y = c} with unit normal (a, b). Its positive side is ℓ⁺ = {a x + b y > c}.
struct Line2 {
  double a = 0, b = 1, c = 0;
  /// The line through p and q (p ≠ q), oriented so that ℓ⁺ lies to the left of p→q.
  static Line2 through(Vec2d p, Vec2d q) {
    const Vec2d d = q - p;
    const double len = length(d);
    const double a = -d.y / len, b = d.x / len;
    return {a, b, a * p.x + b * p.y};
  }
  /// Signed distance of p: positive on ℓ⁺, negative on ℓ⁻.
  double eval(Vec2d p) const { return a * p.x + b * p.y - c; }
};

/// A closed segment from a to b.
struct Segment2 {
  Vec2d a, b;
  /// The point at parameter t ∈ [0, 1].
  Vec2d at(double t) const { return lerp(a, b, t); }
};

/// A ray o + t d for t in [tmin, tmax].
struct Ray2 {
  Vec2d o, d;
  double tmin = 0;
  double tmax = std::numeric_limits<double>::infinity();
};

/// Which side of a line something lies on, up to the tolerance.
enum class Side { kPositive, kNegative, kOn, kBoth };

/// Side of a point at signed distance d, counting |d| <= eps as on the line.
inline Side side_of(double d, double eps) {
  return d > eps ? Side::kPositive : (d < -eps ? Side::kNegative : Side::kOn);
}

/// Side of the piece of a segment between signed distances d0 and d1 of its ends: kBoth when the
/// ends lie strictly beyond eps on opposite sides, kOn when both are within eps, else the side of
/// the end beyond eps.
inline Side side_of_piece(double d0, double d1, double eps) {
  const Side s0 = side_of(d0, eps), s1 = side_of(d1, eps);
  if (s0 == s1) return s0;
  if (s0 == Side::kOn) return s1;
  if (s1 == Side::kOn) return s0;
  return Side::kBoth;
}

/// Orientation of c relative to the directed line a→b: +1 left, -1 right, 0 when c lies within
/// eps of the line (eps a distance). Doubles with a tolerance, not an exact predicate: inputs are
/// rejected when they come closer than the tolerance (see accel2d/scene2d.h), so no decision of
/// the laboratory depends on the sign of a quantity below it.
int orientation(Vec2d a, Vec2d b, Vec2d c, double eps);

/// The closest parameter t in [ray.tmin, ray.tmax] where the ray meets the closed segment s, or
/// +inf when it does not. A ray along a collinear segment meets it where it enters it. The one
/// kernel that every 2D structure and brute force share, so their answers agree bit for bit.
double intersect(const Ray2& ray, const Segment2& s);

/// The ray parameters [t0, t1] inside box (slab test, Kay and Kajiya 1986, "Ray tracing complex
/// scenes"); returns false when the ray misses it on [ray.tmin, ray.tmax].
bool ray_box_interval(const Ray2& ray, const Box2d& box, double& t0, double& t1);

/// True when the segment s meets the box grown by eps on every side (Liang and Barsky 1984, "A new
/// concept and method for line clipping").
bool segment_overlaps_box(const Segment2& s, const Box2d& box, double eps);

/// True when the closed segments p and q share a point (or come closer than eps); sets
/// `collinear_overlap` when they overlap along a common line.
bool segments_meet(const Segment2& p, const Segment2& q, double eps, bool& collinear_overlap);

}  // namespace penumbra
