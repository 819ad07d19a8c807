#pragma once
/// Triangulation of one polygon of a mesh file (an OBJ face), given by its 3D vertices in order:
/// the fan (0, i, i + 1) when the polygon is convex, ear clipping otherwise, and a report of what
/// is wrong with it (not planar, no area, self-intersecting, too large to ear-clip).
///
/// - The polygon is projected onto the plane of its Newell normal (Tampieri 1992, "Newell's
///   method for computing the plane equation of a polygon", Graphics Gems III) by dropping the
///   normal's dominant axis; the two axes kept are ordered so that the polygon turns
///   counter-clockwise seen from the normal. The projected coordinates are the input floats.
/// - Orientation tests are made in double with Shewchuk's error bound (Shewchuk 1997, "Adaptive
///   precision floating-point arithmetic and fast robust geometric predicates", orient2d's first
///   stage): a sign is used only when it is certain, otherwise the three points count as
///   collinear.
/// - Convex (every turn left or straight, no reversal, and the boundary winds once): the fan, the
///   triangles of a fan-only reader. Otherwise ear clipping (Meisters 1975, "Polygons have ears";
///   the bookkeeping of Eberly 2002, "Triangulation by ear clipping"): a convex vertex whose
///   triangle holds no reflex or straight vertex is cut off; only the two neighbours of a cut
///   vertex are re-examined. When no ear is left, a straight vertex (collinear, repeated or a
///   spike) is cut off as a zero-area triangle; when neither is left (a polygon that crosses or
///   touches itself), the rest is fan-triangulated and reported.
/// - Every polygon of n vertices gives n - 2 triangles, each with the polygon's winding: a
///   triangle's normal points along the Newell normal, as the fan's does.
/// - Cost: O(n) for convex polygons; O(n^2) for the others, so those of more than
///   kMaxEarClipVertices vertices get the fan instead (reported), and one triangulator (one
///   file) ear-clips concave polygons only until their n^2 add up to its budget (by default
///   kEarClipBudget); later ones get the fan (reported), so no file costs more than a few
///   seconds of ear clipping.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/core/vec.h"
#include "penumbra/geometry/segment2d.h"

namespace penumbra {

/// A polygon with a vertex further from its plane than this fraction of its size (the diagonal of
/// its bounding box) is "not planar".
inline constexpr double kPlanarTolerance = 1e-3;

/// The largest concave polygon that is ear-clipped (O(n^2): 0.1 to 0.2 s at this size on one
/// core); larger ones are fan-triangulated. Convex polygons of any size get the fan in O(n).
inline constexpr size_t kMaxEarClipVertices = 10000;

/// The ear-clipping work one PolygonTriangulator spends by default, as the sum of n^2 over the
/// concave polygons it ear-clips: 20 polygons of kMaxEarClipVertices (2 to 4 s on one core), or
/// 1.2 * 10^8 concave quadrilaterals.
inline constexpr double kEarClipBudget = 2e9;

/// What PolygonTriangulator::triangulate found; nothing set for a planar simple polygon.
struct PolygonReport {
  /// Largest distance of a vertex from the polygon's Newell plane (through its centroid),
  /// divided by the polygon's size; 0 for triangles and polygons with no area.
  double off_plane = 0;
  /// Zero area (all vertices collinear or coincident): fan-triangulated, degenerate triangles.
  bool no_area = false;
  /// Concave with more than kMaxEarClipVertices vertices: fan-triangulated instead.
  bool too_many_vertices = false;
  /// Concave, and the triangulator's ear-clipping budget was spent: fan-triangulated instead.
  bool budget_spent = false;
  /// Two edges cross (in the projection); `crossing_edges` are their first corners (0-based).
  bool crossing = false;
  size_t crossing_edges[2] = {0, 0};
  /// Vertices left when ear clipping found nothing to cut off; they were fan-triangulated.
  size_t stuck_vertices = 0;

  /// True when the polygon is not planar by kPlanarTolerance.
  bool non_planar() const { return off_plane > kPlanarTolerance; }
  /// True when any problem was found.
  bool any() const {
    return non_planar() || no_area || too_many_vertices || budget_spent || crossing ||
           stuck_vertices > 0;
  }
};

/// Triangulates polygons one at a time, reusing its buffers between calls.
class PolygonTriangulator {
 public:
  /// A triangulator that ear-clips concave polygons while the sum of their n^2 stays within
  /// `ear_clip_budget`.
  explicit PolygonTriangulator(double ear_clip_budget = kEarClipBudget)
      : budget_left_(ear_clip_budget) {}

  /// Appends the n - 2 triangles of the polygon `points` (3 <= n < 2^32, finite) to `triangles`
  /// as indices into `points`, three per triangle; returns what it found.
  PolygonReport triangulate(std::span<const Vec3> points, std::vector<uint32_t>& triangles);

 private:
  bool is_convex() const;
  void find_crossing(PolygonReport& report);
  void ear_clip(std::vector<uint32_t>& triangles, PolygonReport& report);
  bool is_ear(uint32_t v) const;
  void update(uint32_t v);
  void cut(uint32_t v, std::vector<uint32_t>& triangles);
  void drop_stale_blockers();

  std::vector<Vec2d> p_;        // the projected polygon, counter-clockwise
  std::vector<uint32_t> prev_;  // ear clipping: the ring of vertices left
  std::vector<uint32_t> next_;
  std::vector<int8_t> turn_;        // orientation at each vertex: +1 convex, 0 straight, -1 reflex
  std::vector<uint8_t> alive_;      // not yet cut off
  std::vector<uint8_t> ear_;        // convex and no blocker in its triangle
  std::vector<uint8_t> blocking_;   // listed in blockers_
  std::vector<uint32_t> blockers_;  // vertices that were reflex or straight (some no longer are)
  std::vector<uint32_t> ears_;      // candidates to cut (checked against ear_ when taken)
  std::vector<uint32_t> straight_;  // candidates among straight vertices (checked when taken)
  std::vector<uint32_t> order_;     // edges by their smallest x, for the crossing test
  size_t cuts_since_cleanup_ = 0;
  double budget_left_;  // ear-clipping work left, in n^2 units
};

}  // namespace penumbra
