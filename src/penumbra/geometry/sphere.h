#pragma once
/// Ray-sphere intersection.
#include <cmath>

#include "penumbra/core/ray.h"

namespace penumbra {

/// Tests the sphere (center, radius) against `r` on (tmin, tmax); on a hit sets t and returns true.
/// Computed in double with the discriminant of Haines et al. 2019 ("Precision Improvements for
/// Ray/Sphere Intersection", Ray Tracing Gems ch. 7), which stays accurate for distant spheres.
inline bool intersect_sphere(const Ray& r, Vec3 center, float radius, float tmin, float tmax,
                             float& t) {
  const double fx = double(r.o.x) - center.x, fy = double(r.o.y) - center.y,
               fz = double(r.o.z) - center.z;
  const double dx = r.d.x, dy = r.d.y, dz = r.d.z;
  const double a = dx * dx + dy * dy + dz * dz;
  const double b = -(fx * dx + fy * dy + fz * dz);  // -b/2 of the textbook quadratic
  // r^2 - |f + (b/a) d|^2: the squared distance from the chord's midpoint, computed stably.
  const double s = b / a;
  const double lx = fx + s * dx, ly = fy + s * dy, lz = fz + s * dz;
  const double rr = double(radius) * radius;
  const double disc = a * (rr - (lx * lx + ly * ly + lz * lz));
  if (!(disc >= 0.0)) return false;
  const double sq = std::sqrt(disc);
  // Stable roots: q = b + sign(b) sqrt(disc); t0 = c / q, t1 = q / a.
  const double c = fx * fx + fy * fy + fz * fz - rr;
  const double q = b + std::copysign(sq, b);
  double t0 = q != 0.0 ? c / q : 0.0, t1 = q / a;
  if (t0 > t1) std::swap(t0, t1);
  // The nearer root beyond tmin, then tmax on its float value: which root is taken must not
  // depend on tmax, so that the same t is found whatever the closest hit so far (hit.h,
  // tie_bound). With t0 >= tmax the far root lies beyond tmax too, as before.
  const double root = t0 > tmin ? t0 : t1;
  if (!(root > tmin)) return false;
  t = static_cast<float>(root);
  return t > tmin && t < tmax;
}

}  // namespace penumbra
