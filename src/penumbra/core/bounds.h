#pragma once
/// Axis-aligned bounding boxes.
#include "penumbra/core/ray.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// An axis-aligned box [lo, hi]; the default box is empty (lo = +inf, hi = -inf).
struct Bounds3 {
  Vec3 lo{kInfinity};
  Vec3 hi{-kInfinity};

  constexpr Bounds3() = default;
  constexpr Bounds3(Vec3 a, Vec3 b) : lo(min(a, b)), hi(max(a, b)) {}
  /// Box of a single point.
  static constexpr Bounds3 of_point(Vec3 p) { return Bounds3(p, p); }

  constexpr bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  constexpr void extend(Vec3 p) { lo = min(lo, p), hi = max(hi, p); }
  constexpr void extend(const Bounds3& b) { lo = min(lo, b.lo), hi = max(hi, b.hi); }
  constexpr Vec3 diagonal() const { return hi - lo; }
  constexpr Vec3 center() const { return (lo + hi) * 0.5f; }
  /// Surface area; zero for an empty box.
  constexpr float surface_area() const {
    if (empty()) return 0.0f;
    const Vec3 d = diagonal();
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  /// Axis of greatest extent.
  constexpr int max_extent_axis() const { return max_dimension(diagonal()); }
  constexpr bool contains(Vec3 p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
  constexpr bool operator==(const Bounds3&) const = default;
};

/// Union of two boxes.
constexpr Bounds3 join(Bounds3 a, const Bounds3& b) {
  a.extend(b);
  return a;
}

}  // namespace penumbra
