#include "penumbra/geometry/convex_polygon2d.h"

namespace penumbra {

double signed_area2(std::span<const Vec2d> poly) {
  double a = 0;
  for (size_t i = 0, n = poly.size(); i < n; ++i) a += cross(poly[i], poly[(i + 1) % n]);
  return a;
}

bool is_convex(std::span<const Vec2d> poly, double eps) {
  const size_t n = poly.size();
  if (n < 3) return false;
  int turn = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2d a = poly[i], b = poly[(i + 1) % n], c = poly[(i + 2) % n];
    if (a == b) return false;
    const int o = orientation(a, b, c, eps);
    if (o == 0) continue;
    if (turn != 0 && o != turn) return false;
    turn = o;
  }
  return turn != 0;
}

std::vector<Vec2d> clip_convex(std::span<const Vec2d> poly, const Line2& line, bool positive,
                               double eps) {
  std::vector<Vec2d> out;
  const size_t n = poly.size();
  const double sign = positive ? 1.0 : -1.0;
  bool beyond = false;
  for (size_t i = 0; i < n; ++i) {
    const Vec2d p = poly[i], q = poly[(i + 1) % n];
    const double dp = sign * line.eval(p), dq = sign * line.eval(q);
    beyond = beyond || dp > eps;
    if (dp >= 0) out.push_back(p);
    // An edge crossing the line strictly adds its crossing point.
    if ((dp > 0 && dq < 0) || (dp < 0 && dq > 0)) out.push_back(lerp(p, q, dp / (dp - dq)));
  }
  if (!beyond) out.clear();
  return out;
}

namespace {

/// True when the projections of p and q on the normal of edge a→b are separated (gap >= -eps).
bool separated_on(Vec2d a, Vec2d b, std::span<const Vec2d> p, std::span<const Vec2d> q,
                  double eps) {
  const Vec2d e = b - a;
  const double len = length(e);
  if (len == 0) return false;
  const Vec2d n{-e.y / len, e.x / len};
  double plo = INFINITY, phi = -INFINITY, qlo = INFINITY, qhi = -INFINITY;
  for (Vec2d v : p) plo = std::min(plo, dot(n, v)), phi = std::max(phi, dot(n, v));
  for (Vec2d v : q) qlo = std::min(qlo, dot(n, v)), qhi = std::max(qhi, dot(n, v));
  return qlo - phi >= -eps || plo - qhi >= -eps;
}

}  // namespace

bool convex_overlap(std::span<const Vec2d> p, std::span<const Vec2d> q, double eps) {
  for (size_t i = 0; i < p.size(); ++i)
    if (separated_on(p[i], p[(i + 1) % p.size()], p, q, eps)) return false;
  for (size_t i = 0; i < q.size(); ++i)
    if (separated_on(q[i], q[(i + 1) % q.size()], p, q, eps)) return false;
  return true;
}

double intersect_polygon(const Ray2& ray, std::span<const Vec2d> poly) {
  const size_t n = poly.size();
  if (n == 2) return intersect(ray, {poly[0], poly[1]});
  double best = INFINITY;
  for (size_t i = 0; i < n; ++i)
    best = std::min(best, intersect(ray, {poly[i], poly[(i + 1) % n]}));
  return best;
}

bool clip_line(std::span<const Vec2d> poly, const Line2& line, Segment2& chord) {
  // The crossing points of the edges, ordered along the line's direction (b, -a).
  const Vec2d dir{line.b, -line.a};
  double lo = INFINITY, hi = -INFINITY;
  Vec2d plo, phi;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2d p = poly[i], q = poly[(i + 1) % n];
    const double dp = line.eval(p), dq = line.eval(q);
    Vec2d x;
    if (dp == 0)
      x = p;
    else if ((dp < 0) != (dq < 0) && dq != 0)
      x = lerp(p, q, dp / (dp - dq));
    else
      continue;
    const double u = dot(x, dir);
    if (u < lo) lo = u, plo = x;
    if (u > hi) hi = u, phi = x;
  }
  if (!(lo < hi)) return false;
  chord = {plo, phi};
  return true;
}

}  // namespace penumbra
