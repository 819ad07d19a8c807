#include "penumbra/accel/collision/collision.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/collision/swept_tests.h"
#include "penumbra/accel/collision/triangle_triangle.h"
#include "penumbra/core/error.h"

namespace penumbra::collision {

namespace {

/// Relative padding of the swept volumes' culling boxes, against the rounding of the slab test
/// and of the exact tests' distances (thousands of units in the last place: never decisive for
/// speed, always enough for conservative culling).
constexpr double kPadding = 1e-12;

/// Closed overlap of two node boxes (lo.x, hi.x, lo.y, hi.y, lo.z, hi.z).
inline bool overlap(const float* a, const float* b) {
  return a[0] <= b[1] && b[0] <= a[1] && a[2] <= b[3] && b[2] <= a[3] && a[4] <= b[5] &&
         b[4] <= a[5];
}
inline bool overlap(const Bounds3& a, const Bounds3& b) {
  return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
         a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
}
/// Half the surface area of a node box: the size by which the descent picks the node to split.
inline float half_area(const BvhNode& n) {
  const float dx = n.box[1] - n.box[0], dy = n.box[3] - n.box[2], dz = n.box[5] - n.box[4];
  return dx * dy + dy * dz + dz * dx;
}

double max_abs(const DVec3& v) {
  return std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
}

/// The box swept by a query: a segment origin + s dir, s in [0, 1], thickened by `extent` on
/// each axis (a sphere's radius, a box's half sizes, plus padding). A node box meets it when
/// the segment meets the node box grown by `extent`: a slab test (Kay and Kajiya 1986,
/// "Ray Tracing Complex Scenes") with per-query reciprocals computed once.
class SweptVolume {
 public:
  SweptVolume(const DVec3& origin, const DVec3& dir, const DVec3& extent, const Bounds3& scene)
      : origin_(origin), dir_(dir) {
    double m = std::max(max_abs(origin), max_abs(origin + dir));
    m = std::max(m, max_abs(extent));
    if (!scene.empty())
      m = std::max(m, std::max(max_abs(DVec3(scene.lo)), max_abs(DVec3(scene.hi))));
    const double pad = kPadding * m;
    for (int k = 0; k < 3; ++k) {
      extent_[k] = extent[k] + pad;
      inv_dir_[k] = dir[k] != 0 ? 1.0 / dir[k] : 0.0;
    }
  }

  /// True when the volume may meet the box [lo, hi] (never false when it does).
  bool meets(const float lo[3], const float hi[3]) const {
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
      const double l = double(lo[k]) - extent_[k], h = double(hi[k]) + extent_[k];
      if (!(l <= h)) return false;  // empty box
      if (dir_[k] == 0) {
        if (origin_[k] < l || origin_[k] > h) return false;
        continue;
      }
      double ta = (l - origin_[k]) * inv_dir_[k], tb = (h - origin_[k]) * inv_dir_[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
      if (t0 > t1) return false;
    }
    return true;
  }
  bool meets(const BvhNode& n) const {
    const float lo[3] = {n.box[0], n.box[2], n.box[4]}, hi[3] = {n.box[1], n.box[3], n.box[5]};
    return meets(lo, hi);
  }
  bool meets(const Bounds3& b) const {
    const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    return meets(lo, hi);
  }

 private:
  DVec3 origin_, dir_, inv_dir_, extent_;
};

/// Triangles of `mesh` whose boxes meet `volume` and that pass `exact(triangle)`, sorted.
template <class Exact>
std::vector<uint32_t> sweep_query(const CollisionMesh& mesh, const SweptVolume& volume,
                                  const Exact& exact, QueryStats* stats) {
  std::vector<uint32_t> out;
  const BvhNodeArray& nodes = mesh.nodes();
  QueryStats local;
  ++local.node_tests;
  if (nodes.empty() || !volume.meets(nodes[0])) {
    if (stats) *stats = local;
    return out;
  }
  std::array<uint32_t, kBvhStackSize + 2> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = nodes[stack[--top]];
    if (node.is_leaf()) {
      for (uint32_t k = node.index; k < node.index + node.count; ++k) {
        const uint32_t id = mesh.leaf_ids()[k];
        if (!mesh.valid(id) || !volume.meets(mesh.triangle_box(id))) continue;
        ++local.exact_tests;
        if (exact(mesh.triangle(id))) out.push_back(id);
      }
      continue;
    }
    for (uint32_t c = node.index; c < node.index + 2; ++c) {
      ++local.node_tests;
      if (volume.meets(nodes[c])) stack[top++] = c;
    }
  }
  std::sort(out.begin(), out.end());
  if (stats) *stats = local;
  return out;
}

}  // namespace

void check_query(const MovingSphere& s) {
  if (!is_finite(s.from) || !is_finite(s.to) || !std::isfinite(s.radius) || s.radius < 0)
    throw Error(fmt::format("moving sphere: need finite centres and a radius >= 0, got radius {}",
                            s.radius));
}

void check_query(const MovingBox& b) {
  const DBox& box = b.box;
  if (!is_finite(box.lo) || !is_finite(box.hi) || !is_finite(b.displacement))
    throw Error("moving box: corners and displacement must be finite");
  if (box.lo.x > box.hi.x || box.lo.y > box.hi.y || box.lo.z > box.hi.z)
    throw Error(fmt::format("moving box: min ({}, {}, {}) exceeds max ({}, {}, {})", box.lo.x,
                            box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z));
}

std::vector<TrianglePair> intersecting_pairs(const CollisionMesh& a, const CollisionMesh& b,
                                             QueryStats* stats) {
  std::vector<TrianglePair> out;
  const BvhNodeArray &na = a.nodes(), &nb = b.nodes();
  QueryStats local;
  if (na.empty() || nb.empty()) {
    if (stats) *stats = local;
    return out;
  }
  // Simultaneous descent: a stack of node pairs whose boxes overlap. Each step splits the
  // larger node of the pair (or the inner one), so a pair stack of depth(a) + depth(b) + 1
  // entries suffices.
  struct NodePair {
    uint32_t a, b;
  };
  std::array<NodePair, 2 * kBvhStackSize + 2> stack;
  int top = 0;
  ++local.node_tests;
  if (overlap(na[0].box, nb[0].box)) stack[top++] = {0, 0};
  while (top > 0) {
    const NodePair p = stack[--top];
    const BvhNode &x = na[p.a], &y = nb[p.b];
    if (x.is_leaf() && y.is_leaf()) {
      // Leaf pair: triangle boxes, then the exact test.
      for (uint32_t i = x.index; i < x.index + x.count; ++i) {
        const uint32_t ia = a.leaf_ids()[i];
        if (!a.valid(ia)) continue;
        const Bounds3& box_a = a.triangle_box(ia);
        for (uint32_t j = y.index; j < y.index + y.count; ++j) {
          const uint32_t ib = b.leaf_ids()[j];
          if (!b.valid(ib) || !overlap(box_a, b.triangle_box(ib))) continue;
          ++local.exact_tests;
          if (valid_triangles_intersect(a.triangle(ia), b.triangle(ib))) out.push_back({ia, ib});
        }
      }
      continue;
    }
    const bool split_a = !x.is_leaf() && (y.is_leaf() || half_area(x) >= half_area(y));
    if (split_a) {
      for (uint32_t c = x.index; c < x.index + 2; ++c) {
        ++local.node_tests;
        if (overlap(na[c].box, y.box)) stack[top++] = {c, p.b};
      }
    } else {
      for (uint32_t c = y.index; c < y.index + 2; ++c) {
        ++local.node_tests;
        if (overlap(x.box, nb[c].box)) stack[top++] = {p.a, c};
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (stats) *stats = local;
  return out;
}

std::vector<uint32_t> touched_triangles(const CollisionMesh& mesh, const MovingSphere& sphere,
                                        QueryStats* stats) {
  check_query(sphere);
  const double r = sphere.radius;
  const SweptVolume volume(sphere.from, sphere.to - sphere.from, {r, r, r}, mesh.bounds());
  return sweep_query(
      mesh, volume,
      [&](const DTriangle& t) { return moving_sphere_touches(t, sphere.from, sphere.to, r); },
      stats);
}

std::vector<uint32_t> touched_triangles(const CollisionMesh& mesh, const MovingBox& box,
                                        QueryStats* stats) {
  check_query(box);
  const DBox& b = box.box;
  const DVec3 centre = (b.lo + b.hi) * 0.5, half = (b.hi - b.lo) * 0.5;
  const SweptVolume volume(centre, box.displacement, half, mesh.bounds());
  return sweep_query(
      mesh, volume, [&](const DTriangle& t) { return moving_box_touches(t, b, box.displacement); },
      stats);
}

}  // namespace penumbra::collision
