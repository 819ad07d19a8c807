#pragma once
/// Ray-parallelogram intersection.
#include <cmath>

#include "penumbra/core/ray.h"

namespace penumbra {

/// Tests the parallelogram {p + u e1 + v e2 : u, v in [0, 1]} against `r` on (tmin, tmax); on a
/// hit sets t, u, v and returns true. A degenerate parallelogram is never hit.
inline bool intersect_quad(const Ray& r, Vec3 p, Vec3 e1, Vec3 e2, float tmin, float tmax,
                           float& t, float& u, float& v) {
  // Möller-Trumbore style with the parallelogram's edges: solve o + t d = p + u e1 + v e2.
  const Vec3 pv = cross(r.d, e2);
  const float det = dot(e1, pv);
  if (!(std::fabs(det) > 0.0f)) return false;
  const float inv = 1.0f / det;
  const Vec3 s = r.o - p;
  const float uu = dot(s, pv) * inv;
  if (!(uu >= 0.0f && uu <= 1.0f)) return false;
  const Vec3 qv = cross(s, e1);
  const float vv = dot(r.d, qv) * inv;
  if (!(vv >= 0.0f && vv <= 1.0f)) return false;
  const float tt = dot(e2, qv) * inv;
  if (!(tt > tmin && tt < tmax)) return false;
  t = tt, u = uu, v = vv;
  return true;
}

}  // namespace penumbra
