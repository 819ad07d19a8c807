#include "penumbra/geometry/polygon_triangulator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "penumbra/core/dvec3.h"

namespace penumbra {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1: the unit roundoff of double
// Shewchuk's bound on the rounding error of orient2d's determinant, relative to the sum of the
// magnitudes of its two products (ccwerrboundA).
constexpr double kOrientBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;

/// +1 when a, b, c turn counter-clockwise, -1 clockwise, 0 when they are collinear or too close
/// to it for double to tell.
int orient(Vec2d a, Vec2d b, Vec2d c) {
  const double left = (a.x - c.x) * (b.y - c.y), right = (a.y - c.y) * (b.x - c.x);
  const double det = left - right, bound = kOrientBound * (std::fabs(left) + std::fabs(right));
  return det > bound ? 1 : (det < -bound ? -1 : 0);
}

/// True when p lies in the closed counter-clockwise triangle (a, b, c); a point too close to an
/// edge to tell counts as on it.
bool in_triangle(Vec2d a, Vec2d b, Vec2d c, Vec2d p) {
  return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

/// True when segments ab and cd cross at a point inside both (segments that touch or overlap
/// along a line do not cross).
bool segments_cross(Vec2d a, Vec2d b, Vec2d c, Vec2d d) {
  return orient(a, b, c) * orient(a, b, d) < 0 && orient(c, d, a) * orient(c, d, b) < 0;
}

/// Appends the fan (ring[0], ring[i], ring[i + 1]).
void append_fan(std::span<const uint32_t> ring, std::vector<uint32_t>& triangles) {
  for (size_t i = 1; i + 1 < ring.size(); ++i)
    triangles.insert(triangles.end(), {ring[0], ring[i], ring[i + 1]});
}

/// Appends the fan of the polygon 0, 1, ..., n - 1.
void append_fan(size_t n, std::vector<uint32_t>& triangles) {
  for (size_t i = 1; i + 1 < n; ++i) {
    const auto j = static_cast<uint32_t>(i);
    triangles.insert(triangles.end(), {0, j, j + 1});
  }
}

}  // namespace

PolygonReport PolygonTriangulator::triangulate(std::span<const Vec3> points,
                                               std::vector<uint32_t>& triangles) {
  const size_t n = points.size();
  PolygonReport report;
  if (n <= 3) {
    append_fan(n, triangles);
    return report;
  }

  // Newell normal (twice the vector area) and size, relative to the first vertex for accuracy.
  const DVec3 origin(points[0]);
  DVec3 normal, centroid, lo, hi;
  for (size_t i = 0; i < n; ++i) {
    const DVec3 q = DVec3(points[i]) - origin, r = DVec3(points[(i + 1) % n]) - origin;
    normal = normal + cross(q, r);
    centroid = centroid + q;
    lo = min(lo, q);
    hi = max(hi, q);
  }
  const double size = length(hi - lo), area2 = length(normal);
  // No area: below what the rounding of the sum above can produce from collinear vertices.
  if (!(area2 > std::max(1e-12, 4.0 * kEpsilon * double(n)) * size * size)) {
    report.no_area = true;
    append_fan(n, triangles);
    return report;
  }

  // Distance from the plane through the centroid.
  const DVec3 unit = normal * (1.0 / area2);
  centroid = centroid * (1.0 / double(n));
  double off = 0;
  for (size_t i = 0; i < n; ++i)
    off = std::max(off, std::fabs(dot(unit, DVec3(points[i]) - origin - centroid)));
  report.off_plane = off / size;

  // Project: drop the dominant axis k, keep (k + 1, k + 2), swapped when the normal points down
  // that axis, so that the polygon is counter-clockwise in the plane.
  const DVec3 mag(std::fabs(normal.x), std::fabs(normal.y), std::fabs(normal.z));
  const int k = mag.x >= mag.y && mag.x >= mag.z ? 0 : (mag.y >= mag.z ? 1 : 2);
  int u = (k + 1) % 3, v = (k + 2) % 3;
  if (normal[k] < 0) std::swap(u, v);
  p_.resize(n);
  for (size_t i = 0; i < n; ++i) p_[i] = {points[i][u], points[i][v]};

  // Convex polygons keep the fan; large concave ones get it too, reported.
  if (is_convex()) {
    append_fan(n, triangles);
    return report;
  }
  if (n > kMaxEarClipVertices) {
    report.too_many_vertices = true;
    append_fan(n, triangles);
    return report;
  }
  const double work = double(n) * double(n);
  if (work > budget_left_) {
    report.budget_spent = true;
    append_fan(n, triangles);
    return report;
  }
  budget_left_ -= work;
  find_crossing(report);
  ear_clip(triangles, report);
  return report;
}

// Convex: no right turn, no reversal (a straight vertex where the boundary turns back), and the
// boundary winds once. With no right turn the edge direction turns monotonically, by 2π per
// winding; each winding changes the sign of the x direction twice, so more than two changes
// mean a star polygon such as the pentagram.
bool PolygonTriangulator::is_convex() const {
  const size_t n = p_.size();
  int sign_changes = 0, last_sign = 0, first_sign = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2d a = p_[(i + n - 1) % n], b = p_[i], c = p_[(i + 1) % n];
    const int o = orient(a, b, c);
    if (o < 0 || (o == 0 && dot(b - a, c - b) < 0)) return false;
    const double dx = c.x - b.x;
    const int sign = dx > 0 ? 1 : (dx < 0 ? -1 : 0);
    if (sign == 0) continue;
    if (first_sign == 0) first_sign = sign;
    if (last_sign != 0 && sign != last_sign) ++sign_changes;
    last_sign = sign;
  }
  if (last_sign != first_sign) ++sign_changes;  // around the end
  return sign_changes <= 2;
}

// A sweep over x: edges sorted by their smallest x, each compared with the edges that start
// before it ends. O(n log n) plus the pairs that overlap in x; O(n^2) at worst.
void PolygonTriangulator::find_crossing(PolygonReport& report) {
  const size_t n = p_.size();
  order_.resize(n);
  for (uint32_t i = 0; i < n; ++i) order_[i] = i;
  const auto xmin = [&](uint32_t e) { return std::min(p_[e].x, p_[(e + 1) % n].x); };
  std::sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
    return xmin(a) < xmin(b) || (xmin(a) == xmin(b) && a < b);  // ties by index: deterministic
  });
  for (size_t s = 0; s < n; ++s) {
    const uint32_t e = order_[s];
    const Vec2d a = p_[e], b = p_[(e + 1) % n];
    const double xmax = std::max(a.x, b.x);
    const double ylo = std::min(a.y, b.y), yhi = std::max(a.y, b.y);
    for (size_t t = s + 1; t < n && xmin(order_[t]) <= xmax; ++t) {
      const uint32_t f = order_[t];
      if (f == (e + 1) % n || e == (f + 1) % n) continue;  // adjacent edges share a vertex
      const Vec2d c = p_[f], d = p_[(f + 1) % n];
      if (std::max(c.y, d.y) < ylo || std::min(c.y, d.y) > yhi) continue;
      if (segments_cross(a, b, c, d)) {
        report.crossing = true;
        report.crossing_edges[0] = std::min(e, f);
        report.crossing_edges[1] = std::max(e, f);
        return;
      }
    }
  }
}

void PolygonTriangulator::ear_clip(std::vector<uint32_t>& triangles, PolygonReport& report) {
  const auto n = static_cast<uint32_t>(p_.size());
  prev_.resize(n);
  next_.resize(n);
  turn_.resize(n);
  alive_.assign(n, 1);
  ear_.assign(n, 0);
  blocking_.assign(n, 0);
  blockers_.clear();
  ears_.clear();
  straight_.clear();
  cuts_since_cleanup_ = 0;
  for (uint32_t i = 0; i < n; ++i) {
    prev_[i] = i == 0 ? n - 1 : i - 1;
    next_[i] = i + 1 == n ? 0 : i + 1;
  }
  // Classify every vertex, then find the ears among the convex ones.
  for (uint32_t i = 0; i < n; ++i) {
    turn_[i] = static_cast<int8_t>(orient(p_[prev_[i]], p_[i], p_[next_[i]]));
    if (turn_[i] <= 0) {
      blocking_[i] = 1;
      blockers_.push_back(i);
    }
    if (turn_[i] == 0) straight_.push_back(i);
  }
  for (uint32_t i = 0; i < n; ++i) {
    ear_[i] = turn_[i] > 0 && is_ear(i);
    if (ear_[i]) ears_.push_back(i);
  }

  // Cut one vertex per step: an ear, else a straight vertex, else give up with the fan.
  uint32_t left = n, last = 0;
  while (left > 3) {
    uint32_t v = kNone;
    while (v == kNone && !ears_.empty()) {
      const uint32_t e = ears_.back();
      ears_.pop_back();
      if (alive_[e] && ear_[e]) v = e;
    }
    while (v == kNone && !straight_.empty()) {
      const uint32_t s = straight_.back();
      straight_.pop_back();
      if (alive_[s] && turn_[s] == 0) v = s;
    }
    if (v == kNone) {
      report.stuck_vertices = left;
      std::vector<uint32_t> ring;
      for (uint32_t i = 0, w = last; i < left; ++i, w = next_[w]) ring.push_back(w);
      append_fan(ring, triangles);
      return;
    }
    last = prev_[v];
    cut(v, triangles);
    --left;
  }
  triangles.insert(triangles.end(), {prev_[last], last, next_[last]});
}

// An ear: convex, and no vertex that is reflex or straight lies in its closed triangle, apart from
// vertices at the triangle's corners (a polygon may pass through a point twice, as polygons with a
// hole cut open do). In a simple polygon, if any vertex lies in the triangle a reflex one does,
// so the others need no test.
bool PolygonTriangulator::is_ear(uint32_t v) const {
  const Vec2d a = p_[prev_[v]], b = p_[v], c = p_[next_[v]];
  const double xlo = std::min({a.x, b.x, c.x}), xhi = std::max({a.x, b.x, c.x});
  const double ylo = std::min({a.y, b.y, c.y}), yhi = std::max({a.y, b.y, c.y});
  for (const uint32_t w : blockers_) {
    const Vec2d q = p_[w];
    if (q.x < xlo || q.x > xhi || q.y < ylo || q.y > yhi) continue;
    if (!alive_[w] || turn_[w] > 0 || q == a || q == b || q == c) continue;
    if (in_triangle(a, b, c, q)) return false;
  }
  return true;
}

// Re-examines v after a neighbour was cut: its turn, and whether it is an ear now.
void PolygonTriangulator::update(uint32_t v) {
  turn_[v] = static_cast<int8_t>(orient(p_[prev_[v]], p_[v], p_[next_[v]]));
  if (turn_[v] <= 0 && !blocking_[v]) {
    blocking_[v] = 1;
    blockers_.push_back(v);
  }
  if (turn_[v] == 0) straight_.push_back(v);
  ear_[v] = turn_[v] > 0 && is_ear(v);
  if (ear_[v]) ears_.push_back(v);
}

// Appends the triangle (prev, v, next), takes v out of the ring and re-examines its neighbours.
// In a simple polygon no other vertex changes: cutting an ear only narrows its neighbours' angles,
// so no vertex becomes reflex, and an ear's triangle stays free of vertices.
void PolygonTriangulator::cut(uint32_t v, std::vector<uint32_t>& triangles) {
  const uint32_t a = prev_[v], c = next_[v];
  triangles.insert(triangles.end(), {a, v, c});
  alive_[v] = 0;
  next_[a] = c;
  prev_[c] = a;
  if (++cuts_since_cleanup_ > blockers_.size() / 2) drop_stale_blockers();
  update(a);
  update(c);
}

// Removes the blockers that were cut or turned convex, so that the ear tests stay proportional
// to the reflex vertices left; amortised O(1) per cut.
void PolygonTriangulator::drop_stale_blockers() {
  cuts_since_cleanup_ = 0;
  std::erase_if(blockers_, [&](uint32_t w) {
    const bool stale = !alive_[w] || turn_[w] > 0;
    if (stale) blocking_[w] = 0;
    return stale;
  });
}

}  // namespace penumbra
