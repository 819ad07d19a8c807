#pragma once
/// Double-precision convex polygons against planes for the BSP build: signed distances with a
/// tolerance, the side of a polygon, and splitting a polygon in two (Sutherland, Hodgman 1974,
/// "Reentrant polygon clipping", CACM 17(1), one plane at a time, keeping both pieces).
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "penumbra/core/vec.h"

namespace penumbra {

/// A 3D point in double precision; the build keeps fragment polygons in it.
struct Vec3d {
  double x = 0, y = 0, z = 0;
  constexpr Vec3d() = default;
  constexpr Vec3d(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  /// Exact conversion of a float point.
  constexpr explicit Vec3d(Vec3 v) : x(v.x), y(v.y), z(v.z) {}
  constexpr Vec3d operator+(Vec3d b) const { return {x + b.x, y + b.y, z + b.z}; }
  constexpr Vec3d operator-(Vec3d b) const { return {x - b.x, y - b.y, z - b.z}; }
  constexpr Vec3d operator*(double s) const { return {x * s, y * s, z * s}; }
};

constexpr double dot(Vec3d a, Vec3d b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3d cross(Vec3d a, Vec3d b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// A splitting plane n.x = d with a unit normal, stored in float exactly as the traversal reads
/// it; the build evaluates it in double, so build and traversal agree on the plane itself.
struct BspPlane {
  Vec3 n;
  float d = 0;

  /// Signed distance of `p` (positive on the side n points to), in double.
  double distance(Vec3d p) const {
    return double(n.x) * p.x + double(n.y) * p.y + double(n.z) * p.z - double(d);
  }
};

/// Where a polygon lies relative to a plane, within the tolerance.
enum class BspSide : uint8_t { kNegative, kPositive, kCoplanar, kStraddling };

/// Side of a vertex with signed distance `s`: -1, 0 (within `eps`) or +1.
inline int side_of(double s, double eps) {
  return s > eps ? 1 : (s < -eps ? -1 : 0);
}

/// Classifies `poly` against `plane`: kCoplanar when every vertex is within `eps`, kPositive when
/// none is below -eps, kNegative when none is above eps, else kStraddling. The distances are
/// written to `dist` (resized) for split_polygon.
inline BspSide classify_polygon(std::span<const Vec3d> poly, const BspPlane& plane, double eps,
                                std::vector<double>& dist) {
  dist.resize(poly.size());
  bool pos = false, neg = false;
  for (size_t i = 0; i < poly.size(); ++i) {
    dist[i] = plane.distance(poly[i]);
    const int s = side_of(dist[i], eps);
    pos |= s > 0, neg |= s < 0;
  }
  if (pos && neg) return BspSide::kStraddling;
  if (pos) return BspSide::kPositive;
  return neg ? BspSide::kNegative : BspSide::kCoplanar;
}

/// Splits the straddling convex polygon `poly` (vertex distances `dist` from classify_polygon)
/// into its parts on either side (Sutherland-Hodgman). Vertices within `eps` go to both parts;
/// an edge from a vertex above eps to one below -eps adds its crossing point to both. Both parts
/// are convex, have at least three vertices, and together cover `poly`.
inline void split_polygon(std::span<const Vec3d> poly, std::span<const double> dist, double eps,
                          std::vector<Vec3d>& pos, std::vector<Vec3d>& neg) {
  pos.clear();
  neg.clear();
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const size_t j = i + 1 == n ? 0 : i + 1;
    const int si = side_of(dist[i], eps), sj = side_of(dist[j], eps);
    if (si >= 0) pos.push_back(poly[i]);
    if (si <= 0) neg.push_back(poly[i]);
    if (si * sj < 0) {  // the edge crosses the plane strictly: both parts get the crossing
      const Vec3d x = poly[i] + (poly[j] - poly[i]) * (dist[i] / (dist[i] - dist[j]));
      pos.push_back(x);
      neg.push_back(x);
    }
  }
}

/// Area of a planar polygon (Newell's normal, half its length).
inline double polygon_area(std::span<const Vec3d> poly) {
  Vec3d n;
  for (size_t i = 0; i < poly.size(); ++i) n = n + cross(poly[i], poly[(i + 1) % poly.size()]);
  return 0.5 * std::sqrt(dot(n, n));
}

/// The plane of a convex polygon from its first three vertices, or nullopt when they do not
/// define one: the normal vanishes, or a vertex lies farther than `eps` from the plane after
/// rounding it to float (a needle so thin that its normal is noise). Then the polygon is kept as
/// a non-planar object.
inline std::optional<BspPlane> polygon_plane(std::span<const Vec3d> poly, double eps) {
  if (poly.size() < 3) return std::nullopt;
  const Vec3d nd = cross(poly[1] - poly[0], poly[2] - poly[0]);
  const double len = std::sqrt(dot(nd, nd));
  if (!(len > 0.0) || !std::isfinite(len)) return std::nullopt;
  BspPlane plane;
  plane.n = Vec3(float(nd.x / len), float(nd.y / len), float(nd.z / len));
  double d = 0;  // offset: the mean over the vertices, against the rounded normal
  const Vec3d nf(plane.n);
  for (const Vec3d& p : poly) d += dot(nf, p);
  plane.d = float(d / double(poly.size()));
  for (const Vec3d& p : poly)
    if (!(std::fabs(plane.distance(p)) <= eps)) return std::nullopt;
  return plane;
}

}  // namespace penumbra
