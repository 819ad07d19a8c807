/// Tests of the kd-tree: parameters, every split criterion against brute force, clipping of
/// primitives to boxes, the event encoding, primitives lying in split planes, rays along split
/// planes, empty-space cut-off, tree invariants (the leaves' triangles by their clipped area) and
/// determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "penumbra/accel/build/kd_clip.h"
#include "penumbra/accel/build/kd_events.h"
#include "penumbra/accel/build/kd_simple_builder.h"
#include "penumbra/accel/kdtree.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

KdTree make(const std::string& spec) {
  return KdTree(ParamList::parse(spec));
}

void add_triangle(PrimitiveSet& prims, Vec3 a, Vec3 b, Vec3 c) {
  TriangleMesh m;
  m.positions = {a, b, c};
  m.indices = {0, 1, 2};
  prims.add_mesh(m, Transform(), 0);
}

/// A leaf or inner node with its cell, from a walk of the tree. Children marked as empty leaves
/// are not stored (the traversal never loads them): they appear with `empty` set.
struct Visit {
  uint32_t node;
  Bounds3 cell;
  int depth;
  bool empty = false;  ///< an empty leaf left out of the node array (`node` is meaningless)
};

std::vector<Visit> walk(const KdTree& kd) {
  std::vector<Visit> out, stack{{0, kd.bounds(), 0}};
  const auto nodes = kd.nodes();
  while (!stack.empty()) {
    const Visit v = stack.back();
    stack.pop_back();
    out.push_back(v);
    if (v.empty) continue;
    const KdNode& n = nodes[v.node];
    if (n.is_leaf()) continue;
    Bounds3 below = v.cell, above = v.cell;
    below.hi[n.axis()] = above.lo[n.axis()] = n.split();
    const uint32_t marked = n.empty_children();
    stack.push_back({n.above(), above, v.depth + 1, (marked & 2u) != 0});
    stack.push_back({v.node + 1, below, v.depth + 1, (marked & 1u) != 0});
  }
  return out;
}

/// Closest hits, and occlusion with infinite and finite tmax, against brute force; returns the
/// number of rays that differ.
size_t differences(const Accelerator& accel, const PrimitiveSet& prims,
                   const std::vector<Ray>& rays) {
  auto brute = make_accelerator("brute");
  brute->build(prims);
  std::vector<uint8_t> bad(rays.size(), 0);
  parallel_for_range(
      rays.size(),
      [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
          Hit ref, got;
          const bool r = brute->intersect(rays[i], ref), g = accel.intersect(rays[i], got);
          bool ok = r == g;
          if (ok && r && got.prim != ref.prim) {  // a tie must be a real hit at the same t
            Hit own;
            own.t = rays[i].tmax;
            prims.intersect(got.prim, PreparedRay(rays[i]), own);
            ok = own.prim == got.prim && own.t == got.t;
          }
          ok = ok && (!r || std::fabs(got.t - ref.t) <= 1e-5f * ref.t);
          ok = ok && accel.occluded(rays[i]) == r;
          if (ok && r) {
            Ray shadow = rays[i];
            shadow.tmax = ref.t * 0.99f;
            ok = accel.occluded(shadow) == brute->occluded(shadow);
          }
          bad[i] = !ok;
        }
      },
      64);
  return size_t(std::count(bad.begin(), bad.end(), 1));
}

TEST(KdTree, ParametersParseWithDefaults) {
  const KdTree kd = make("kdtree");
  EXPECT_EQ(kd.name(), "kdtree:sah");
  EXPECT_EQ(kd.params().criterion, KdCriterion::kSah);
  EXPECT_FLOAT_EQ(kd.params().traversal_cost, 1.0f);
  EXPECT_FLOAT_EQ(kd.params().intersect_cost, 0.4f);
  EXPECT_FLOAT_EQ(kd.params().empty_bonus, 0.1f);
  EXPECT_EQ(kd.params().max_leaf, 0);
  EXPECT_EQ(kd.params().max_depth, 0);
  EXPECT_TRUE(kd.params().clip);
  const KdTree m = make("kdtree:median,leaf=3,depth=20,clip=0");
  EXPECT_EQ(m.name(), "kdtree:median,leaf=3,depth=20,clip=0");
  EXPECT_EQ(m.params().criterion, KdCriterion::kMedian);
  EXPECT_EQ(m.params().max_leaf, 3);
  EXPECT_EQ(m.params().max_depth, 20);
  EXPECT_FALSE(m.params().clip);
  const KdTree g = make("kdtree:gap,ct=2,ci=4,empty_bonus=0.5");
  EXPECT_EQ(g.params().criterion, KdCriterion::kGap);
  EXPECT_EQ(g.params().max_leaf, 8);
  EXPECT_FLOAT_EQ(g.params().traversal_cost, 2.0f);
  EXPECT_FLOAT_EQ(g.params().intersect_cost, 4.0f);
  EXPECT_FLOAT_EQ(g.params().empty_bonus, 0.5f);
  EXPECT_EQ(make_accelerator("kdtree:sah,ci=2")->name(), "kdtree:sah,ci=2");
}

TEST(KdTree, BadParametersAreRejected) {
  for (const char* spec :
       {"kdtree:sah,median", "kdtree:sah=false", "kdtree:leafs=2", "kdtree:ci=0", "kdtree:ci=x",
        "kdtree:ct=-1", "kdtree:empty_bonus=1", "kdtree:depth=0", "kdtree:depth=65",
        "kdtree:leaf=-1", "kdtree:clip=maybe", "kdtree:binned"})
    EXPECT_THROW(make_accelerator(spec), Error) << spec;
}

TEST(KdTree, DepthLimitFollowsPbrt) {
  KdBuildParams p;
  EXPECT_EQ(kd_depth_limit(p, 1), 8);
  EXPECT_EQ(kd_depth_limit(p, 1024), 21);       // 8 + 1.3 * 10
  EXPECT_EQ(kd_depth_limit(p, 1'000'000), 33);  // 8 + 1.3 * 19
  p.max_depth = 12;
  EXPECT_EQ(kd_depth_limit(p, 1'000'000), 12);
}

TEST(KdTree, EveryCriterionAgreesWithBruteForce) {
  const std::vector<TestScene> scenes = {random_soup(800, 31),     room_with_boxes(25, 32),
                                         mixed_shapes(33),         coplanar_grid(8, 8),
                                         degenerate_triangles(34), thin_and_large(35)};
  for (const char* spec :
       {"kdtree:sah", "kdtree:median", "kdtree:gap", "kdtree:sah,clip=0",
        "kdtree:sah,ci=4,empty_bonus=0.5", "kdtree:median,leaf=1", "kdtree:gap,leaf=2"}) {
    uint64_t seed = 40;
    for (const TestScene& s : scenes) {
      KdTree kd = make(spec);
      kd.build(s.prims);
      const auto rays = mixed_rays(s.prims, 6000, seed++);
      EXPECT_EQ(differences(kd, s.prims, rays), 0u) << spec << " on " << s.name;
    }
  }
}

TEST(KdTree, TriangleClippedToABoxIsExact) {
  const Bounds3 box({1, 1, -1}, {3, 3, 1});
  // The right triangle x, y >= 0, x + y <= 4 in z = 0: inside the box it is the square minus
  // the corner beyond x + y = 4, which still reaches (1, 3) and (3, 1).
  const Vec3 tri[3] = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};
  EXPECT_EQ(clip_polygon_bounds(tri, box), Bounds3({1, 1, 0}, {3, 3, 0}));
  // Only the corner (1, 1) of the box touches x + y <= 2.
  const Vec3 small[3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  EXPECT_EQ(clip_polygon_bounds(small, box), Bounds3({1, 1, 0}, {1, 1, 0}));
  // Entirely outside (x + y <= 1.5), entirely inside.
  const Vec3 outside[3] = {{0, 0, 0}, {1.5f, 0, 0}, {0, 1.5f, 0}};
  EXPECT_TRUE(clip_polygon_bounds(outside, box).empty());
  const Vec3 inside[3] = {{1.5f, 1.5f, 0.5f}, {2.5f, 1.5f, -0.5f}, {2, 2.5f, 0}};
  EXPECT_EQ(clip_polygon_bounds(inside, box), Bounds3({1.5f, 1.5f, -0.5f}, {2.5f, 2.5f, 0.5f}));
  // A tilted triangle in the plane z = x + y: inside the unit cube, z <= 1 cuts it to the
  // triangle (0,0,0), (1,0,1), (0,1,1).
  const Vec3 tilted[3] = {{0, 0, 0}, {4, 0, 4}, {0, 4, 4}};
  EXPECT_EQ(clip_polygon_bounds(tilted, Bounds3({0, 0, 0}, {1, 1, 1})),
            Bounds3({0, 0, 0}, {1, 1, 1}));
  EXPECT_EQ(clip_polygon_bounds(tilted, Bounds3({0, 0, 0}, {1, 1, 0.5f})),
            Bounds3({0, 0, 0}, {0.5f, 0.5f, 0.5f}));
  // Non-representable crossings are rounded outward: a third can never be cut off.
  const Vec3 third[3] = {{0, 0, 0}, {3, 0, 1}, {0, 3, 1}};
  const Bounds3 b = clip_polygon_bounds(third, Bounds3({0, 0, 0}, {1, 1, 1}));
  EXPECT_LE(b.lo.z, 0.0f);
  EXPECT_GE(b.hi.z, 2.0 / 3.0);  // at (1, 1): z = 2/3
  EXPECT_LE(b.hi.z, std::nextafter(float(2.0 / 3.0), 1.0f));
}

TEST(KdTree, ClippedAreaIsExact) {
  PrimitiveSet prims;
  add_triangle(prims, {0, 0, 0}, {4, 0, 0}, {0, 4, 0});
  prims.add_quad({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 3)}, 0);
  prims.add_sphere({Vec3(2, 2, 2), 1.0f}, 0);
  const Bounds3 all({-10, -10, -10}, {10, 10, 10});
  EXPECT_DOUBLE_EQ(clip_prim_area(prims, 0, all), 8.0);
  // The square [1, 3]^2 without its corner beyond x + y = 4 (a right triangle of legs 2).
  EXPECT_DOUBLE_EQ(clip_prim_area(prims, 0, Bounds3({1, 1, -1}, {3, 3, 1})), 2.0);
  EXPECT_DOUBLE_EQ(clip_prim_area(prims, 0, Bounds3({5, 5, -1}, {6, 6, 1})), 0.0);
  EXPECT_DOUBLE_EQ(clip_prim_area(prims, 1, all), 6.0);
  EXPECT_DOUBLE_EQ(clip_prim_area(prims, 1, Bounds3({1, -1, 1}, {3, 1, 2})), 1.0);
  EXPECT_EQ(clip_prim_area(prims, 2, all), 0.0);  // no polygon
}

TEST(KdTree, StraddlingPrimitivesSplitIntoTheirParts) {
  PrimitiveSet prims;
  add_triangle(prims, {0, 0, 0}, {4, 0, 0}, {0, 4, 0});
  prims.add_sphere({{0, 0, 0}, 1.0f}, 0);
  prims.add_quad({{0, 0, 0}, {2, 0, 2}, {0, 2, 0}}, 0);
  Bounds3 below, above;
  // Triangle at x = 1: below, x in [0, 1] reaches y = 4; above, y <= 4 - x <= 3.
  split_prim_bounds(prims, 0, prims.prim_bounds(0), 0, 1.0f, true, below, above);
  EXPECT_EQ(below, Bounds3({0, 0, 0}, {1, 4, 0}));
  EXPECT_EQ(above, Bounds3({1, 0, 0}, {4, 3, 0}));
  // Without clipping the box is only cut.
  split_prim_bounds(prims, 0, prims.prim_bounds(0), 0, 1.0f, false, below, above);
  EXPECT_EQ(above, Bounds3({1, 0, 0}, {4, 4, 0}));
  // A sphere's box is cut at the plane.
  split_prim_bounds(prims, 1, prims.prim_bounds(1), 2, 0.5f, true, below, above);
  EXPECT_EQ(below, Bounds3({-1, -1, -1}, {1, 1, 0.5f}));
  EXPECT_EQ(above, Bounds3({-1, -1, 0.5f}, {1, 1, 1}));
  // The parallelogram rises with x: the part with z <= 1 has x <= 1.
  split_prim_bounds(prims, 2, prims.prim_bounds(2), 2, 1.0f, true, below, above);
  EXPECT_EQ(below, Bounds3({0, 0, 0}, {1, 2, 1}));
  EXPECT_EQ(above, Bounds3({1, 0, 1}, {2, 2, 2}));
  // Clipping to a box it does not reach: empty.
  EXPECT_TRUE(clip_prim_bounds(prims, 0, Bounds3({3, 3, -1}, {4, 4, 1})).empty());
}

TEST(KdTree, EventKeysSortLikeTheSweepNeeds) {
  const float xs[] = {-1e30f, -2.5f, -0.0f, 0.0f, 1e-40f, 1.0f, 3.5f, 1e30f};
  for (size_t i = 0; i + 1 < std::size(xs); ++i) {
    EXPECT_LE(kd_float_key(xs[i]), kd_float_key(xs[i + 1]));
    EXPECT_EQ(kd_key_float(kd_float_key(xs[i])), xs[i] + 0.0f);
  }
  EXPECT_EQ(kd_float_key(-0.0f), kd_float_key(0.0f));
  // Axis first, then position, then end < planar < start, then primitive.
  EXPECT_LT(kd_event(0, 5.0f, kKdStart, 9), kd_event(1, -5.0f, kKdEnd, 0));
  EXPECT_LT(kd_event(1, 1.0f, kKdStart, 0), kd_event(1, 2.0f, kKdEnd, 0));
  EXPECT_LT(kd_event(1, 2.0f, kKdEnd, 7), kd_event(1, 2.0f, kKdPlanar, 0));
  EXPECT_LT(kd_event(1, 2.0f, kKdPlanar, 7), kd_event(1, 2.0f, kKdStart, 0));
  const KdEvent e = kd_event(2, -3.25f, kKdPlanar, 12345);
  EXPECT_EQ(kd_event_axis(e), 2);
  EXPECT_EQ(kd_event_pos(e), -3.25f);
  EXPECT_EQ(kd_event_prim(e), 12345u);
  EXPECT_EQ(kd_event_prim(kd_event_with_prim(e, 7)), 7u);
  EXPECT_EQ(kd_event_plane(kd_event_with_prim(e, 7)), kd_event_plane(e));
}

TEST(KdTree, GapPlaneLiesInTheLargestGapNearTheMedian) {
  // Along x: boxes cover [0, 1], [2, 3] and [9, 10]; the window is [2.5, 7.5]; the gap (3, 9)
  // cut to the window is (3, 7.5), so the plane is at 5.25. y and z have no gaps.
  std::vector<KdPrim> prims = {{Bounds3({0, 0, 0}, {1, 10, 10}), 0},
                               {Bounds3({2, 0, 0}, {3, 10, 10}), 1},
                               {Bounds3({9, 0, 0}, {10, 10, 10}), 2}};
  const KdPlane p = kd_gap_plane(prims, Bounds3({0, 0, 0}, {10, 10, 10}));
  EXPECT_EQ(p.axis, 0);
  EXPECT_FLOAT_EQ(p.pos, 5.25f);
  // No gap reaches the windows: none.
  prims = {{Bounds3({0, 0, 0}, {6, 10, 10}), 0}, {Bounds3({4, 0, 0}, {10, 10, 10}), 1}};
  EXPECT_LT(kd_gap_plane(prims, Bounds3({0, 0, 0}, {10, 10, 10})).axis, 0);
}

/// Two clusters of small triangles near z = 1/8 and z = 15/8, and one large triangle lying in
/// z = 1, the spatial median of the longest axis (z spans [1/16, 31/16], x and y [0, 1.8]).
PrimitiveSet planar_scene() {
  PrimitiveSet prims;
  Pcg32 rng(7, 3);
  for (int i = 0; i < 200; ++i) {
    const float z = i % 2 ? 0.125f : 1.875f;
    const Vec3 c(0.1f + 0.7f * rng.next_float(), 0.1f + 0.7f * rng.next_float(), z);
    add_triangle(prims, c, c + Vec3(0.05f, 0, 0.0625f), c + Vec3(0, 0.05f, -0.0625f));
  }
  add_triangle(prims, {0, 0, 1}, {1.8f, 0, 1}, {0, 1.8f, 1});
  return prims;
}

TEST(KdTree, TriangleInASplitPlaneIsFoundFromBothSides) {
  const PrimitiveSet prims = planar_scene();
  const uint32_t big = prims.size() - 1;
  for (const char* spec : {"kdtree:sah", "kdtree:median", "kdtree:gap"}) {
    KdTree kd = make(spec);
    kd.build(prims);
    if (std::string(spec) == "kdtree:median") {
      const KdNode& root = kd.nodes()[0];
      ASSERT_FALSE(root.is_leaf());
      EXPECT_EQ(root.axis(), 2);
      EXPECT_EQ(root.split(), 1.0f);
    }
    Pcg32 rng(9, 1);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 target(0.85f * rng.next_float(), 0.85f * rng.next_float(), 1.0f);
      const float side = i % 2 ? 1.0f : -1.0f;  // from above and from below
      const Vec3 o = target + Vec3(0.1f * (rng.next_float() - 0.5f),
                                   0.1f * (rng.next_float() - 0.5f), 0.3f * side);
      const Ray ray{o, target - o};
      Hit hit;
      ASSERT_TRUE(kd.intersect(ray, hit)) << spec;
      EXPECT_EQ(hit.prim, big) << spec;
      EXPECT_NEAR(hit.t, 1.0f, 1e-5f) << spec;
      EXPECT_TRUE(kd.occluded(ray)) << spec;
    }
  }
}

/// Rays from the split planes of `kd`'s inner nodes, 48 per node until there are more than
/// `max`: an origin uniform in the bounds moved into the plane and a random direction, which
/// `adjust(ray, node, k, rng)` completes (false: leave the ray out).
template <class Adjust>
std::vector<Ray> rays_in_split_planes(const KdTree& kd, uint64_t seed, size_t max, Adjust adjust) {
  std::vector<Ray> rays;
  Pcg32 rng(seed, 5);
  const Bounds3 b = kd.bounds();
  for (const Visit& v : walk(kd)) {
    if (v.empty || kd.nodes()[v.node].is_leaf() || rays.size() > max) continue;
    const KdNode& n = kd.nodes()[v.node];
    for (int k = 0; k < 48; ++k) {
      Ray r;
      r.o = b.lo + b.diagonal() * Vec3(rng.next_float(), rng.next_float(), rng.next_float());
      r.d = normalize(Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - Vec3(0.5f));
      r.o[n.axis()] = n.split();
      if (adjust(r, n, k, rng)) rays.push_back(r);
    }
  }
  return rays;
}

TEST(KdTree, RaysAlongSplitPlanesAgreeWithBruteForce) {
  // Axis-aligned boxes: many faces and edges lie in split planes.
  const TestScene s = room_with_boxes(25, 17);
  for (const char* spec : {"kdtree:sah", "kdtree:median", "kdtree:gap"}) {
    KdTree kd = make(spec);
    kd.build(s.prims);
    const std::vector<Ray> rays =
        rays_in_split_planes(kd, 5, 20000, [](Ray& r, const KdNode& n, int k, Pcg32&) {
          r.d[n.axis()] = k % 2 ? 0.0f : -0.0f;  // in the plane, and staying in it
          if (k % 8 >= 4) {  // along an edge direction too: parallel to a second axis
            const int other = (n.axis() + 1 + k % 2) % 3;
            r.d[other] = 0.0f;
          }
          return r.d != Vec3(0.0f);
        });
    ASSERT_GT(rays.size(), 1000u);
    EXPECT_EQ(differences(kd, s.prims, rays), 0u) << spec;
  }
}

TEST(KdTree, RaysFromSplitPlanesAgreeWithBruteForce) {
  // Rays that start inside the tree descend to their origin's leaf by the side of each plane
  // the origin lies on; an origin in a plane goes to the side the ray leaves it for. Origins in
  // split planes, leaving them up, down or along them, from tmin = 0 and from further on; the
  // room is centred on 0, so that some planes lie at 0 and the origins there are given as -0
  // and as +0.
  EXPECT_FALSE(std::signbit(KdNode::inner(1, -0.0f, 7).split()));
  const TestScene s = room_with_boxes(25, 17, Vec3(-5.0f));
  for (const char* spec : {"kdtree:sah", "kdtree:median", "kdtree:gap"}) {
    KdTree kd = make(spec);
    kd.build(s.prims);
    int at_zero = 0;
    for (const KdNode& n : kd.nodes()) at_zero += !n.is_leaf() && n.split() == 0.0f;
    const std::vector<Ray> rays =
        rays_in_split_planes(kd, 6, 40000, [](Ray& r, const KdNode& n, int k, Pcg32& rng) {
          if (n.split() == 0.0f && k % 2) r.o[n.axis()] = -0.0f;
          const int leave = k % 6;  // up, down, along (+0 or -0), up and down at a grazing angle
          r.d[n.axis()] = leave == 0   ? 0.5f
                          : leave == 1 ? -0.5f
                          : leave == 2 ? 0.0f
                          : leave == 3 ? -0.0f
                          : leave == 4 ? 1e-6f
                                       : -1e-6f;
          if (k % 12 >= 6) r.tmin = 0.5f * rng.next_float();
          return true;
        });
    ASSERT_GT(rays.size(), 1000u) << spec;
    EXPECT_GT(at_zero, 0) << spec;
    EXPECT_EQ(differences(kd, s.prims, rays), 0u) << spec;
  }
}

TEST(KdTree, RaysFromASplitPlaneEnterOnlyTheSideTheyLeaveFor) {
  // Two triangles on either side of x = 0, the median split: a ray from the plane visits the
  // root and the leaf on the side it goes to, whatever the sign of the zero it starts at, and a
  // ray parallel to the plane only its own side. Each of these is one node more when the
  // descent takes the origin's zero or the plane's side wrongly (it stays correct, but tests
  // the other leaf for nothing).
  PrimitiveSet prims;
  add_triangle(prims, {-2, 0, 0}, {-1, 0, 1}, {-1, 1, 0});  // -x + y + z = 2
  add_triangle(prims, {1, 0, 0}, {2, 0, 1}, {2, 1, 0});     // x - y - z = 1
  KdTree kd = make("kdtree:median,leaf=1");
  kd.build(prims);
  ASSERT_EQ(kd.nodes().size(), 3u);
  ASSERT_EQ(kd.nodes()[0].split(), 0.0f);
  struct Case {
    Vec3 o, d;
    uint32_t prim;  ///< kNoPrim: a miss
  };
  const Case cases[] = {
      {{-0.0f, 0.25f, 0.25f}, {1, 0, 0}, 1},       {{0.0f, 0.25f, 0.25f}, {1, 0, 0}, 1},
      {{-0.0f, 0.25f, 0.25f}, {-1, 0, 0}, 0},      {{0.0f, 0.25f, 0.25f}, {-1, 0, 0}, 0},
      {{-0.5f, 0.25f, 0.25f}, {0, 1, 0}, kNoPrim}, {{0.5f, 0.25f, 0.25f}, {0, -0.0f, 1}, kNoPrim}};
  for (const Case& c : cases) {
    TraversalCost cost;
    Hit hit;
    EXPECT_EQ(kd.intersect_cost(Ray{c.o, c.d}, hit, cost), c.prim != kNoPrim);
    EXPECT_EQ(hit.prim, c.prim);
    EXPECT_EQ(cost.nodes, 2u) << "from " << c.o.x << " along " << c.d.x << ", " << c.d.y;
  }
}

TEST(KdTree, EmptySpaceIsCutOff) {
  // A small cluster in one corner of a big box marked by four far clusters: the SAH cuts off
  // the empty space into empty leaves, and one of them holds most of the volume.
  PrimitiveSet prims;
  Pcg32 rng(3, 3);
  for (int i = 0; i < 300; ++i) {
    const Vec3 c(rng.next_float(), rng.next_float(), rng.next_float());
    add_triangle(prims, c, c + Vec3(0.05f, 0, 0), c + Vec3(0, 0.05f, 0.02f));
  }
  for (float x : {0.0f, 100.0f})  // and four small clusters far away
    for (float y : {0.0f, 100.0f})
      for (int i = 0; i < 30; ++i) {
        const Vec3 c(x + rng.next_float(), y + rng.next_float(), 99 + rng.next_float());
        add_triangle(prims, c, c + Vec3(0.05f, 0, 0), c + Vec3(0, 0.05f, 0.02f));
      }
  KdTree kd = make("kdtree");
  kd.build(prims);
  const AccelStats st = kd.stats();
  const auto empty = std::find_if(st.extra.begin(), st.extra.end(),
                                  [](const auto& kv) { return kv.first == "empty leaves"; });
  ASSERT_NE(empty, st.extra.end());
  EXPECT_GT(empty->second, 0.0);
  const Vec3 d = kd.bounds().diagonal();
  const double root_volume = double(d.x) * d.y * d.z;
  double largest = 0;
  size_t empty_leaves = 0;
  for (const Visit& v : walk(kd)) {
    if (!v.empty) {
      // Only marked empty leaves are left out of the array.
      const KdNode& n = kd.nodes()[v.node];
      EXPECT_FALSE(n.is_leaf() && n.count() == 0 && v.depth > 0);
      continue;
    }
    ++empty_leaves;
    const Vec3 e = v.cell.diagonal();
    largest = std::max(largest, double(e.x) * e.y * e.z / root_volume);
  }
  EXPECT_EQ(double(empty_leaves), empty->second);
  EXPECT_GT(largest, 0.5);
}

TEST(KdTree, TreeInvariantsHold) {
  for (const char* spec : {"kdtree:sah", "kdtree:median", "kdtree:gap"}) {
    for (const TestScene& s : {random_soup(1500, 1), mixed_shapes(2), degenerate_triangles(3)}) {
      KdTree kd = make(spec);
      kd.build(s.prims);
      SCOPED_TRACE(std::string(spec) + " on " + s.name);
      const AccelStats st = kd.stats();
      std::vector<int> referenced(s.prims.size(), 0);
      size_t leaves = 0, refs = 0, max_depth = 0;
      std::vector<int> reached(kd.nodes().size(), 0);
      size_t stored = 0, empty_leaves = 0;
      for (const Visit& v : walk(kd)) {
        max_depth = std::max(max_depth, size_t(v.depth));
        if (v.empty) {
          ++leaves, ++empty_leaves;
          continue;
        }
        ++stored;
        ASSERT_LT(v.node, kd.nodes().size());
        EXPECT_EQ(++reached[v.node], 1) << v.node;
        const KdNode& n = kd.nodes()[v.node];
        if (!n.is_leaf()) {
          EXPECT_GT(n.split(), v.cell.lo[n.axis()]);
          EXPECT_LT(n.split(), v.cell.hi[n.axis()]);
          // The traversal reads the next node of every inner node (to prefetch).
          EXPECT_LT(v.node + 1, kd.nodes().size());
          continue;
        }
        // The traversal skips the children marked empty without loading them, and those are
        // left out of the array: a stored leaf other than the root is not empty.
        if (v.depth > 0) {
          EXPECT_GT(n.count(), 0u) << v.node;
        }
        ++leaves;
        refs += n.count();
        for (uint32_t i = n.first(); i < n.first() + n.count(); ++i) {
          const uint32_t id = kd.refs()[i];
          ++referenced[id];
          // The primitive really reaches the cell (its clipped part is not empty).
          EXPECT_FALSE(clip_prim_bounds(s.prims, id, v.cell).empty()) << id;
          // Triangles in blocks: the largest part inside the cell first, then by id.
          if (s.prims.all_triangles() && i > n.first()) {
            const uint32_t prev = kd.refs()[i - 1];
            const double a = clip_prim_area(s.prims, prev, v.cell);
            const double b = clip_prim_area(s.prims, id, v.cell);
            EXPECT_TRUE(a > b || (a == b && prev < id)) << prev << " before " << id;
          }
        }
      }
      for (uint32_t id = 0; id < s.prims.size(); ++id)
        EXPECT_EQ(referenced[id] > 0, referenced_by_structures(s.prims, id)) << id;
      EXPECT_EQ(st.nodes, 2 * leaves - 1);
      EXPECT_EQ(extra_stat(kd, "stored nodes"), double(kd.nodes().size()));
      EXPECT_EQ(extra_stat(kd, "empty leaves"), double(empty_leaves));
      // Every stored node is reached, but the below one of two empty children, kept so that
      // each inner node has a next node.
      EXPECT_LE(stored, kd.nodes().size());
      EXPECT_GE(stored + empty_leaves / 2, kd.nodes().size());
      EXPECT_EQ(st.leaves, leaves);
      EXPECT_EQ(st.prim_refs, refs);
      EXPECT_EQ(st.max_depth, max_depth);
      EXPECT_LE(int(max_depth), kd_depth_limit(kd.params(), s.prims.size()));
      const size_t padded = kd.refs().size();
      EXPECT_EQ(st.bytes, kd.nodes().size() * sizeof(KdNode) + padded * sizeof(uint32_t) +
                              (s.prims.all_triangles() ? padded / 4 * sizeof(TriangleBlock) : 0));
    }
  }
}

TEST(KdTree, SameTreeForEveryThreadCount) {
  const TestScene s = torus(120, 120);  // 28,800 triangles: the top levels build in parallel
  std::vector<KdNode> reference;
  std::vector<uint32_t> reference_refs;
  for (int threads : {1, 2, 4}) {
    const ThreadLimit limit(threads);
    KdTree kd = make("kdtree");
    kd.build(s.prims);
    if (reference.empty()) {
      reference.assign(kd.nodes().begin(), kd.nodes().end());
      reference_refs.assign(kd.refs().begin(), kd.refs().end());
      continue;
    }
    ASSERT_EQ(kd.nodes().size(), reference.size()) << threads;
    EXPECT_EQ(std::memcmp(kd.nodes().data(), reference.data(), reference.size() * sizeof(KdNode)),
              0);
    EXPECT_TRUE(std::equal(kd.refs().begin(), kd.refs().end(), reference_refs.begin()));
  }
}

TEST(KdTree, IdenticalPrimitivesStopAtTheDepthLimit) {
  PrimitiveSet prims;
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int i = 0; i < 3000; ++i) m.indices.insert(m.indices.end(), {0, 1, 2});
  prims.add_mesh(m, Transform(), 0);
  for (const char* spec : {"kdtree:sah", "kdtree:median", "kdtree:gap"}) {
    KdTree kd = make(spec);
    kd.build(prims);
    EXPECT_LE(int(kd.stats().max_depth), kd_depth_limit(kd.params(), 3000)) << spec;
    Hit hit;
    EXPECT_TRUE(kd.intersect({{0.2f, 0.2f, 1.0f}, {0, 0, -1}}, hit)) << spec;
    EXPECT_FLOAT_EQ(hit.t, 1.0f);
  }
}

}  // namespace
}  // namespace penumbra::test
