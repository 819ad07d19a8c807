#include "penumbra/geometry/segment2d.h"

namespace penumbra {

namespace {

/// Distance from p to the closed segment s.
double point_segment_distance(Vec2d p, const Segment2& s) {
  const Vec2d e = s.b - s.a;
  const double ee = dot(e, e);
  const double t = ee > 0 ? std::clamp(dot(p - s.a, e) / ee, 0.0, 1.0) : 0.0;
  return length(p - s.at(t));
}

}  // namespace

int orientation(Vec2d a, Vec2d b, Vec2d c, double eps) {
  const Vec2d e = b - a;
  const double d = cross(e, c - a) / length(e);
  return d > eps ? 1 : (d < -eps ? -1 : 0);
}

double intersect(const Ray2& ray, const Segment2& s) {
  constexpr double kMiss = std::numeric_limits<double>::infinity();
  const Vec2d e = s.b - s.a, w = s.a - ray.o;
  const double denom = cross(ray.d, e);
  if (denom != 0) {
    // Solve o + t d = a + u e by Cramer's rule.
    const double t = cross(w, e) / denom, u = cross(w, ray.d) / denom;
    if (u < 0 || u > 1 || t < ray.tmin || t > ray.tmax) return kMiss;
    return t;
  }
  // Parallel: a hit only when collinear, where the ray enters the segment.
  if (cross(w, ray.d) != 0) return kMiss;
  const double dd = dot(ray.d, ray.d);
  const double ta = dot(s.a - ray.o, ray.d) / dd, tb = dot(s.b - ray.o, ray.d) / dd;
  const double enter = std::max(std::min(ta, tb), ray.tmin),
               leave = std::min(std::max(ta, tb), ray.tmax);
  return enter <= leave ? enter : kMiss;
}

bool ray_box_interval(const Ray2& ray, const Box2d& box, double& t0, double& t1) {
  t0 = ray.tmin;
  t1 = ray.tmax;
  const double o[2] = {ray.o.x, ray.o.y}, d[2] = {ray.d.x, ray.d.y};
  const double lo[2] = {box.lo.x, box.lo.y}, hi[2] = {box.hi.x, box.hi.y};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0) {
      if (o[k] < lo[k] || o[k] > hi[k]) return false;
      continue;
    }
    const double inv = 1.0 / d[k];
    double ta = (lo[k] - o[k]) * inv, tb = (hi[k] - o[k]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

bool segment_overlaps_box(const Segment2& s, const Box2d& box, double eps) {
  // Liang–Barsky: shrink [u0, u1] by the four boundaries of the grown box.
  double u0 = 0, u1 = 1;
  const Vec2d e = s.b - s.a;
  const double p[4] = {-e.x, e.x, -e.y, e.y};
  const double q[4] = {s.a.x - (box.lo.x - eps), (box.hi.x + eps) - s.a.x, s.a.y - (box.lo.y - eps),
                       (box.hi.y + eps) - s.a.y};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
      continue;
    }
    const double r = q[k] / p[k];
    if (p[k] < 0)
      u0 = std::max(u0, r);
    else
      u1 = std::min(u1, r);
    if (u0 > u1) return false;
  }
  return true;
}

bool segments_meet(const Segment2& p, const Segment2& q, double eps, bool& collinear_overlap) {
  collinear_overlap = false;
  const int o1 = orientation(p.a, p.b, q.a, eps), o2 = orientation(p.a, p.b, q.b, eps);
  const int o3 = orientation(q.a, q.b, p.a, eps), o4 = orientation(q.a, q.b, p.b, eps);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // a proper crossing
  if (o1 == 0 && o2 == 0) {
    // Both ends of q on p's line: overlap when their projections on p overlap by more than eps.
    const Vec2d e = p.b - p.a;
    const double len = length(e);
    const double ta = dot(q.a - p.a, e) / len, tb = dot(q.b - p.a, e) / len;
    const double lo = std::max(0.0, std::min(ta, tb)), hi = std::min(len, std::max(ta, tb));
    if (hi - lo > eps) {
      collinear_overlap = true;
      return true;
    }
  }
  // Otherwise they meet only if an endpoint comes within eps of the other segment.
  return point_segment_distance(q.a, p) <= eps || point_segment_distance(q.b, p) <= eps ||
         point_segment_distance(p.a, q) <= eps || point_segment_distance(p.b, q) <= eps;
}

}  // namespace penumbra
