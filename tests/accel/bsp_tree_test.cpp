/// Tests of the auto-partition BSP tree: determinism per seed, fragments tiling their triangles
/// and lying in their node's plane and region, coplanar primitives kept whole at one node, every
/// order and the depth cap against brute force, parameters and the fragment budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "penumbra/accel/bsp_tree.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

BspBuildResult build(const PrimitiveSet& prims, const std::string& spec,
                     const BspFragmentSink* sink = nullptr) {
  return build_bsp(prims, read_bsp_build_params(ParamList::parse(spec)), sink);
}

/// Area of primitive `id` in double (triangles and parallelograms).
double prim_area(const PrimitiveSet& prims, uint32_t id) {
  Vec3d a, b;
  if (prims.kind(id) == PrimKind::kTriangle) {
    const Vec3* p = prims.triangle(id);
    a = Vec3d(p[1]) - Vec3d(p[0]), b = Vec3d(p[2]) - Vec3d(p[0]);
    const Vec3d n = cross(a, b);
    return 0.5 * std::sqrt(dot(n, n));
  }
  const QuadData& q = prims.quad(id);
  const Vec3d n = cross(Vec3d(q.e1), Vec3d(q.e2));
  return std::sqrt(dot(n, n));
}

/// For every node, the planes of its ancestors with the side it lies on (+1 above, -1 below).
std::vector<std::vector<std::pair<uint32_t, int>>> ancestors(const BspBuildResult& t) {
  std::vector<std::vector<std::pair<uint32_t, int>>> up(t.nodes.size());
  for (uint32_t i = 0; i < t.nodes.size(); ++i) {
    if (t.nodes[i].is_leaf()) continue;
    for (int s = 0; s < 2; ++s) {
      const uint32_t c = t.nodes[i].child[s];
      if (c == kBspEmpty) continue;
      EXPECT_GT(c, i) << "children follow their parent (depth-first order)";
      EXPECT_LT(c, t.nodes.size());
      up[c] = up[i];
      up[c].push_back({i, s ? 1 : -1});
    }
  }
  return up;
}

TEST(BspTree, SameSeedGivesTheSameTreeAndOtherSeedsOthers) {
  const TestScene s = random_soup(800, 3);
  const BspBuildResult a = build(s.prims, "bsp:seed=7"), b = build(s.prims, "bsp:seed=7");
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BspNode)), 0);
  EXPECT_EQ(a.refs, b.refs);
  EXPECT_EQ(a.fragments, b.fragments);
  EXPECT_EQ(a.max_depth, b.max_depth);
  auto x = make_accelerator("bsp:seed=7"), y = make_accelerator("bsp:seed=7");
  x->build(s.prims);
  y->build(s.prims);
  EXPECT_EQ(x->stats().nodes, y->stats().nodes);
  EXPECT_EQ(x->stats().extra, y->stats().extra);
  for (const char* other : {"bsp:seed=8", "bsp", "bsp:order=first"}) {
    const BspBuildResult c = build(s.prims, other);
    const bool same =
        c.nodes.size() == a.nodes.size() && c.refs == a.refs &&
        std::memcmp(c.nodes.data(), a.nodes.data(), a.nodes.size() * sizeof(BspNode)) == 0;
    EXPECT_FALSE(same) << other;
    EXPECT_NE(c.fragments, a.fragments) << other;
  }
}

TEST(BspTree, FragmentsTileTheirPolygonsInTheirNodesPlaneAndRegion) {
  // Triangles and parallelograms (the mixed scene's spheres are objects, not fragments).
  for (const TestScene& s : {random_soup(600, 4), mixed_shapes(5)}) {
    for (const char* spec : {"bsp", "bsp:order=first", "bsp:order=fewest-cuts", "bsp:depth=6"}) {
      SCOPED_TRACE(s.name + " " + spec);
      std::map<uint32_t, double> area;
      std::vector<std::tuple<uint32_t, uint32_t, std::vector<Vec3d>>> frags;
      const BspFragmentSink sink = [&](uint32_t prim, uint32_t node, std::span<const Vec3d> poly) {
        area[prim] += polygon_area(poly);
        frags.emplace_back(prim, node, std::vector<Vec3d>(poly.begin(), poly.end()));
      };
      const BspBuildResult t = build(s.prims, spec, &sink);
      EXPECT_EQ(frags.size(), t.fragments);
      size_t planar = 0;
      for (uint32_t id = 0; id < s.prims.size(); ++id) {
        if (s.prims.kind(id) == PrimKind::kSphere) continue;
        ++planar;
        ASSERT_TRUE(area.count(id)) << "prim " << id << " has no fragment";
        EXPECT_NEAR(area[id], prim_area(s.prims, id), 1e-5 * prim_area(s.prims, id)) << id;
      }
      EXPECT_EQ(planar, t.planar);
      // Each fragment lies in its node's plane (inner nodes) and on its side of every ancestor's.
      const double eps = 2.0 * kBspBuildEps * t.scale;
      const auto up = ancestors(t);
      for (const auto& [prim, node, poly] : frags) {
        const BspNode& n = t.nodes[node];
        const auto refs = std::span(t.refs).subspan(n.first, n.count);
        EXPECT_TRUE(std::find(refs.begin(), refs.end(), prim) != refs.end());
        for (const Vec3d& v : poly) {
          if (!n.is_leaf()) {
            EXPECT_LE(std::fabs(BspPlane{n.n, n.d}.distance(v)), eps);
          }
          for (const auto& [a, side] : up[node]) {
            const BspPlane plane{t.nodes[a].n, t.nodes[a].d};
            EXPECT_GE(side * plane.distance(v), -eps);
          }
        }
      }
    }
  }
}

TEST(BspTree, CoplanarQuadsStayWholeAtOneNode) {
  PrimitiveSet prims;
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i)
      prims.add_quad({Vec3(float(i), float(j), 2.0f), Vec3(1, 0, 0), Vec3(0, 1, 0)}, 0);
  for (const char* spec : {"bsp", "bsp:order=first", "bsp:order=fewest-cuts"}) {
    BspTree bsp(ParamList::parse(spec));
    bsp.build(prims);
    ASSERT_EQ(bsp.nodes().size(), 1u) << spec;
    EXPECT_EQ(bsp.nodes()[0].count, 100u);
    const AccelStats st = bsp.stats();
    EXPECT_EQ(st.nodes, 3u);  // the root and its two empty cells
    EXPECT_EQ(st.leaves, 2u);
    EXPECT_EQ(st.max_depth, 1u);
    EXPECT_EQ(st.prim_refs, 100u);
    EXPECT_EQ(st.extra[0], std::make_pair(std::string("fragments"), 100.0));
    EXPECT_EQ(st.extra[1], std::make_pair(std::string("fragments_per_triangle"), 1.0));
    Hit hit;  // through a corner shared by four quads, and along the plane
    EXPECT_TRUE(bsp.intersect({{3.0f, 4.0f, 5.0f}, {0, 0, -1}}, hit));
    EXPECT_EQ(hit.t, 3.0f);
    EXPECT_FALSE(bsp.intersect({{-1.0f, 4.5f, 2.0f}, {1, 0, 0}}, hit));
    EXPECT_FALSE(bsp.occluded({{-1.0f, 4.5f, 2.0f}, {1, 0, 0}}));
  }
  // Two parallel grids of triangles: each is stored at one node, nothing is cut.
  const TestScene g = coplanar_grid(20, 20);
  const BspBuildResult t = build(g.prims, "bsp");
  EXPECT_EQ(t.fragments, g.prims.size());
  ASSERT_EQ(t.nodes.size(), 2u);
  EXPECT_EQ(t.nodes[0].count, 800u);
  EXPECT_EQ(t.nodes[1].count, 800u);
}

TEST(BspTree, EveryOrderAndTheDepthCapAgreeWithBrute) {
  const char* specs[] = {"bsp:order=first", "bsp:order=fewest-cuts,candidates=4",
                         "bsp:seed=5,depth=5", "bsp:order=fewest-cuts,depth=12"};
  for (const TestScene& s : {random_soup(500, 6), mixed_shapes(7), room_with_boxes(15, 8),
                             thin_and_large(9), degenerate_triangles(10), torus(30, 20)}) {
    const auto rays = mixed_rays(s.prims, 6000, 11);
    auto brute = make_accelerator("brute");
    brute->build(s.prims);
    std::vector<Hit> ref(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) brute->intersect(rays[i], ref[i]);
    for (const char* spec : specs) {
      auto bsp = make_accelerator(spec);
      bsp->build(s.prims);
      size_t differ = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        Hit h;
        const bool hit = bsp->intersect(rays[i], h);
        differ += hit != ref[i].valid() || (hit && std::fabs(h.t - ref[i].t) > 1e-5f * ref[i].t);
        differ += bsp->occluded(rays[i]) != ref[i].valid();
      }
      EXPECT_EQ(differ, 0u) << spec << " on " << s.name;
    }
  }
}

TEST(BspTree, DepthCapLeavesHoldTheRemainingFragments) {
  const TestScene s = random_soup(400, 12);
  BspTree bsp(ParamList::parse("bsp:depth=4"));
  bsp.build(s.prims);
  const AccelStats st = bsp.stats();
  EXPECT_LE(st.max_depth, 4u);
  size_t capped = 0;
  for (const BspNode& n : bsp.nodes()) capped += n.is_leaf() && n.count > 0;
  EXPECT_GT(capped, 0u);
  EXPECT_EQ(st.extra[4], std::make_pair(std::string("capped_leaves"), double(capped)));
}

TEST(BspTree, SpheresAndDegeneratePolygonsAreObjectsInLeaves) {
  const TestScene s = mixed_shapes(13);
  BspTree bsp(ParamList::parse("bsp"));
  bsp.build(s.prims);
  const auto refs = bsp.refs();
  size_t spheres = 0;
  for (uint32_t id = 0; id < s.prims.size(); ++id) spheres += s.prims.kind(id) == PrimKind::kSphere;
  size_t object_refs = 0, leaf_refs = 0;
  std::vector<bool> seen(s.prims.size());
  for (const BspNode& n : bsp.nodes()) {
    for (uint32_t i = n.first; i < n.first + n.count; ++i) {
      const bool sphere = s.prims.kind(refs[i]) == PrimKind::kSphere;
      if (!n.is_leaf()) {
        EXPECT_FALSE(sphere) << "a sphere at an inner node";
      }
      object_refs += sphere;
      leaf_refs += n.is_leaf();
      seen[refs[i]] = true;
    }
  }
  EXPECT_GE(object_refs, spheres);  // straddling spheres are pushed to both sides
  EXPECT_EQ(bsp.stats().extra[2], std::make_pair(std::string("object_refs"), double(leaf_refs)));
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](bool b) { return b; }));
  // Degenerate triangles (no plane) become objects too; non-finite ones are skipped.
  const TestScene d = degenerate_triangles(14);
  const BspBuildResult t = build(d.prims, "bsp");
  EXPECT_GT(t.object_refs, 0u);
  EXPECT_LT(t.planar, d.prims.size());
}

TEST(BspTree, FewestCutsCutsLessThanRandom) {
  const TestScene s = random_soup(1500, 15);
  const BspBuildResult r = build(s.prims, "bsp"), f = build(s.prims, "bsp:order=fewest-cuts");
  EXPECT_LT(f.fragments, r.fragments);
}

TEST(BspTree, MaxFragmentsStopsTheBuildWithAnError) {
  const TestScene s = random_soup(1000, 16);
  auto bsp = make_accelerator("bsp:max_fragments=1100");
  try {
    bsp->build(s.prims);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("max_fragments=1100"), std::string::npos) << e.what();
  }
}

TEST(BspTree, ParametersAreReadAndChecked) {
  EXPECT_EQ(make_accelerator("bsp")->name(), "bsp");
  EXPECT_EQ(make_accelerator("bsp:seed=3,order=random")->name(), "bsp:order=random,seed=3");
  EXPECT_EQ(make_accelerator("bsp:order=fewest-cuts,candidates=8,depth=40")->name(),
            "bsp:candidates=8,depth=40,order=fewest-cuts");
  BspTree t(ParamList::parse("bsp:order=fewest-cuts,candidates=8,depth=40,max_fragments=99"));
  EXPECT_EQ(t.build_params().order, BspOrder::kFewestCuts);
  EXPECT_EQ(t.build_params().candidates, 8);
  EXPECT_EQ(t.build_params().max_depth, 40);
  EXPECT_EQ(t.build_params().max_fragments, 99u);
  for (const char* bad : {"bsp:order=best", "bsp:order=first,seed=2", "bsp:candidates=8",
                          "bsp:order=fewest-cuts,candidates=0", "bsp:depth=0", "bsp:depth=1025",
                          "bsp:depth=x", "bsp:max_fragments=0", "bsp:seed=-1", "bsp:leaf=4"})
    EXPECT_THROW(make_accelerator(bad), Error) << bad;
}

}  // namespace
}  // namespace penumbra::test
