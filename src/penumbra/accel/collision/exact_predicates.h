#pragma once
/// Exact orientation predicates on double coordinates (Shewchuk 1997, "Adaptive Precision
/// Floating-Point Arithmetic and Fast Robust Geometric Predicates"): a floating-point evaluation
/// with a forward error bound answers almost every call; the rest are evaluated exactly with
/// floating-point expansions. The sign is exact for every finite input (barring overflow and
/// underflow of intermediate products), so tests built on these predicates make consistent
/// decisions on touching, coplanar and collinear configurations.
#include "penumbra/accel/collision/dvec3.h"

namespace penumbra::collision {

/// Sign (-1, 0, +1) of det[b - a, c - a, d - a] = dot(d - a, (b - a) x (c - a)): +1 when d lies
/// on the side of the plane abc into which the normal (b - a) x (c - a) points, 0 when coplanar.
int orient3d(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d);

/// orient3d(a, b, c, d) for one plane abc and many points d: the plane's cross product and the
/// magnitudes of its error bound are computed once (a triangle against three vertices).
class PlaneOrientation {
 public:
  PlaneOrientation(const DVec3& a, const DVec3& b, const DVec3& c);
  /// Equals orient3d(a, b, c, d).
  int operator()(const DVec3& d) const;

 private:
  DVec3 a_, b_, c_;
  DVec3 normal_;     ///< (b - a) x (c - a), rounded
  DVec3 permanent_;  ///< per axis, the sum of the absolute products of that normal component
};

/// Sign (-1, 0, +1) of (b - a) x (c - a) for points of the plane: +1 when a, b, c turn
/// counterclockwise, 0 when collinear.
int orient2d(double ax, double ay, double bx, double by, double cx, double cy);

/// Calls of the exact (slow) stage since the program started, all threads (for tests).
unsigned long long exact_predicate_fallbacks();

}  // namespace penumbra::collision
