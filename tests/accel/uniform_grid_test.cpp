/// Tests of the uniform grid: parameters, resolution and caps, the exact cell membership, rays
/// along cell boundaries, the mailbox, determinism across thread counts and the reference budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "penumbra/accel/build/prim_box_overlap.h"
#include "penumbra/accel/registry.h"
#include "penumbra/accel/uniform_grid.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/core/timer.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

/// `b` grown by eight overlap pads on each side.
Bounds3 grown(const Bounds3& b) {
  Bounds3 g = b;
  for (int a = 0; a < 3; ++a) {
    const float pad = 8.0f * float(kOverlapPad) * (std::fabs(b.lo[a]) + std::fabs(b.hi[a]));
    g.lo[a] -= pad, g.hi[a] += pad;
  }
  return g;
}

UniformGrid build_grid(const std::string& spec, const PrimitiveSet& prims) {
  UniformGrid g(ParamList::parse(spec));
  g.build(prims);
  return g;
}

/// Brute-force closest hits.
std::vector<Hit> brute_hits(const PrimitiveSet& prims, const std::vector<Ray>& rays) {
  auto brute = make_accelerator("brute");
  brute->build(prims);
  std::vector<Hit> hits(rays.size());
  parallel_for(
      rays.size(), [&](size_t i) { brute->intersect(rays[i], hits[i]); }, 256);
  return hits;
}

/// Closest hits and occlusion of `spec` on `rays` must agree exactly with `ref` (same t).
void expect_same_hits(const std::string& spec, const PrimitiveSet& prims,
                      const std::vector<Ray>& rays, const std::vector<Hit>& ref) {
  auto accel = make_accelerator(spec);
  accel->build(prims);
  size_t differ = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit a;
    accel->intersect(rays[i], a);
    differ += a.valid() != ref[i].valid() || a.t != ref[i].t ||
              accel->occluded(rays[i]) != ref[i].valid();
  }
  EXPECT_EQ(differ, 0u) << spec;
}

TEST(UniformGrid, ParametersAreParsedAndRejectedStrictly) {
  EXPECT_EQ(make_accelerator("grid")->name(), "grid");
  EXPECT_EQ(make_accelerator("grid:lambda=4")->name(), "grid:lambda=4");
  for (const char* good : {"grid:res=64", "grid:res=64x32x16", "grid:mailbox=0", "grid:mailbox=64",
                           "grid:copy=0", "grid:lambda=0.5"})
    EXPECT_NO_THROW(make_accelerator(good)) << good;
  for (const char* bad :
       {"grid:res=64x32", "grid:res=0", "grid:res=abc", "grid:res=5000", "grid:res=8x8x8x8",
        "grid:res=8x", "grid:res=-4", "grid:lambda=0", "grid:lambda=100", "grid:mailbox=12",
        "grid:lambda=2,res=8", "grid:cells=8", "grid:copy=2"})
    EXPECT_THROW(make_accelerator(bad), Error) << bad;
}

TEST(UniformGrid, ResolutionGivesNearCubicCellsWithinTheCaps) {
  using R = std::array<int, 3>;
  EXPECT_EQ(grid_resolution({1, 1, 1}, 1000, 8.0), (R{20, 20, 20}));
  EXPECT_EQ(grid_resolution({4, 2, 1}, 1000, 8.0), (R{40, 20, 10}));
  // A flat or very thin axis gets one cell and the others share the budget.
  EXPECT_EQ(grid_resolution({1, 1, 0}, 1000, 4.0), (R{63, 63, 1}));
  EXPECT_EQ(grid_resolution({1, 1, 0.001f}, 1000, 4.0), (R{63, 63, 1}));
  EXPECT_EQ(grid_resolution({0, 0, 0}, 10, 2.0), (R{1, 1, 1}));
  // Per-axis and total caps.
  EXPECT_EQ(grid_resolution({1000, 1, 1}, 1'000'000, 4.0)[0], kMaxAxisCells);
  const R big = grid_resolution({1, 1, 1}, 10'000'000, 64.0);
  EXPECT_LE(size_t(big[0]) * big[1] * big[2], kMaxCells);
  const R capped = cap_resolution({4096, 4096, 4096}, 100);
  EXPECT_LE(size_t(capped[0]) * capped[1] * capped[2], kMinCellCap);
  EXPECT_GE(capped[0], 100);  // scaled down uniformly, not collapsed
}

TEST(UniformGrid, CellsHoldExactlyTheOverlappingPrimitives) {
  for (const TestScene& s : {mixed_shapes(3), coplanar_grid(6, 6), room_with_boxes(8, 4),
                             degenerate_triangles(5), thin_and_large(6)}) {
    for (const char* spec : {"grid", "grid:res=7x5x6"}) {
      SCOPED_TRACE(s.name + " " + spec);
      const UniformGrid g = build_grid(spec, s.prims);
      const auto res = g.resolution();
      // Every primitive overlapping a cell is listed (ascending); a listed one overlaps it at
      // least within a few pads (box shortcuts may keep one that misses by less).
      size_t refs = 0, nonempty = 0;
      for (int z = 0; z < res[2]; ++z)
        for (int y = 0; y < res[1]; ++y)
          for (int x = 0; x < res[0]; ++x) {
            const auto cell = g.cell(x, y, z);
            const Bounds3 box = g.cell_bounds(x, y, z);
            EXPECT_TRUE(std::is_sorted(cell.begin(), cell.end()));
            for (uint32_t id = 0; id < s.prims.size(); ++id) {
              if (s.prims.prim_bounds(id).empty()) continue;
              if (!referenced_by_structures(s.prims, id)) {  // never hit: left out
                EXPECT_FALSE(std::binary_search(cell.begin(), cell.end(), id)) << "prim " << id;
                continue;
              }
              const bool listed = std::binary_search(cell.begin(), cell.end(), id);
              if (prim_box_overlap(s.prims, id, box)) {
                ASSERT_TRUE(listed)
                    << "prim " << id << " missing from " << x << " " << y << " " << z;
              } else if (listed) {
                ASSERT_TRUE(prim_box_overlap(s.prims, id, grown(box))) << "prim " << id;
              }
            }
            refs += cell.size();
            nonempty += !cell.empty();
          }
      const AccelStats st = g.stats();
      EXPECT_EQ(st.nodes, size_t(res[0]) * size_t(res[1]) * size_t(res[2]));
      EXPECT_EQ(st.leaves, nonempty);
      EXPECT_EQ(st.prim_refs, refs);
      EXPECT_EQ(st.max_depth, 0u);
      ASSERT_GE(st.extra.size(), 3u);
      EXPECT_EQ(st.extra[0].first, "nx");
      EXPECT_EQ(st.extra[0].second, res[0]);
    }
  }
}

/// Two triangles far apart that fix the scene box to about [0, 1]^3, plus `extra`.
PrimitiveSet unit_box_scene(const std::vector<std::array<Vec3, 3>>& extra) {
  PrimitiveSet prims;
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {0.01f, 0, 0}, {0, 0.01f, 0}, {1, 1, 1}, {0.99f, 1, 1}, {1, 0.99f, 1}};
  for (const auto& t : extra) m.positions.insert(m.positions.end(), t.begin(), t.end());
  for (uint32_t i = 0; i < m.positions.size(); ++i) m.indices.push_back(i);
  prims.add_mesh(m, Transform(), 0);
  return prims;
}

TEST(UniformGrid, TriangleInACellFacePlaneIsInBothCells) {
  // Find the plane between the two x cells of a 2x1x1 grid, then put a triangle exactly in it.
  const float plane = build_grid("grid:res=2x1x1", unit_box_scene({})).cell_bounds(0, 0, 0).hi.x;
  const PrimitiveSet prims =
      unit_box_scene({{Vec3(plane, 0.2f, 0.2f), Vec3(plane, 0.8f, 0.2f), Vec3(plane, 0.5f, 0.8f)}});
  const UniformGrid g = build_grid("grid:res=2x1x1", prims);
  ASSERT_EQ(g.cell_bounds(0, 0, 0).hi.x, plane);
  for (int x = 0; x < 2; ++x) {
    const auto c = g.cell(x, 0, 0);
    EXPECT_TRUE(std::find(c.begin(), c.end(), 2u) != c.end()) << "cell " << x;
  }
}

TEST(UniformGrid, RaysAlongCellBoundariesHitOnce) {
  // Rays lying in the grid's own boundary planes and along its cell edges (taken from the built
  // grid, so exactly on them), through a scene of shared edges and coplanar quads.
  const TestScene s = coplanar_grid(8, 8);
  for (const char* spec : {"grid:res=17x17x1", "grid:res=17x17x2", "grid", "grid:res=3x5x7"}) {
    const UniformGrid g = build_grid(spec, s.prims);
    const auto res = g.resolution();
    Pcg32 rng(17, 3);
    const auto plane = [&](int axis) {
      const int k = int(rng.next_bounded(uint32_t(res[axis])));
      return g.cell_bounds(axis == 0 ? k : 0, axis == 1 ? k : 0, axis == 2 ? k : 0).lo[axis];
    };
    std::vector<Ray> rays;
    for (int i = 0; i < 20000; ++i) {
      const float fx = rng.next_float() * 8.5f, fy = rng.next_float() * 8.5f;
      const float dx = rng.next_float() - 0.5f, dy = rng.next_float() - 0.5f;
      switch (i % 4) {
        case 0:
          rays.push_back({{plane(0), plane(1), -1.0f}, {0, 0, 1}});
          break;  // cell edge line
        case 1:
          rays.push_back({{plane(0), fy, 3.0f}, {0, dy, -1}});
          break;  // x plane
        case 2:
          rays.push_back({{fx, plane(1), -2.0f}, {dx, 0, 1}});
          break;  // y plane
        default:
          rays.push_back({{-1.0f, fy, plane(2)}, {1, dy, 0}});
          break;  // z plane
      }
    }
    expect_same_hits(spec, s.prims, rays, brute_hits(s.prims, rays));
  }
}

TEST(UniformGrid, MailboxAndCopyDoNotChangeResults) {
  const TestScene s = random_soup(3000, 21);
  const auto rays = mixed_rays(s.prims, 20000, 22);
  const auto ref = brute_hits(s.prims, rays);
  for (const char* spec : {"grid:mailbox=0", "grid:mailbox=8", "grid", "grid:mailbox=64",
                           "grid:copy=0", "grid:lambda=16"})
    expect_same_hits(spec, s.prims, rays, ref);
}

TEST(UniformGrid, BuildDoesNotDependOnTheThreadCount) {
  const TestScene s = torus(60, 40);
  std::vector<std::vector<uint32_t>> cells[2];
  for (int k = 0; k < 2; ++k) {
    const ThreadLimit limit(k == 0 ? 1 : 0);
    const UniformGrid g = build_grid("grid:lambda=4", s.prims);
    const auto r = g.resolution();
    for (int z = 0; z < r[2]; ++z)
      for (int y = 0; y < r[1]; ++y)
        for (int x = 0; x < r[0]; ++x) {
          const auto c = g.cell(x, y, z);
          EXPECT_TRUE(std::is_sorted(c.begin(), c.end()));
          cells[k].emplace_back(c.begin(), c.end());
        }
  }
  EXPECT_EQ(cells[0], cells[1]);
}

TEST(UniformGrid, LargeOverlappingPrimitivesStayWithinTheReferenceBudget) {
  // 4000 triangles each spanning most of the scene: at lambda * N cells, references would grow
  // as N^(5/3); the budget lowers the resolution instead.
  PrimitiveSet prims;
  TriangleMesh m;
  Pcg32 rng(31, 5);
  const int n = 4000;
  for (int i = 0; i < 3 * n; ++i) {
    m.positions.push_back({rng.next_float(), rng.next_float(), rng.next_float()});
    m.indices.push_back(uint32_t(i));
  }
  prims.add_mesh(m, Transform(), 0);
  const Timer timer;
  const UniformGrid g = build_grid("grid:lambda=64", prims);
  EXPECT_LT(timer.elapsed_ms(), 10'000.0);
  EXPECT_LE(double(g.stats().prim_refs), kMaxCandidatesPerPrim * n);
  const std::vector<Ray> rays = mixed_rays(prims, 2000, 7);
  expect_same_hits("grid:lambda=64", prims, rays, brute_hits(prims, rays));
}

TEST(UniformGrid, FixedResolutionIsCappedLinearly) {
  const TestScene s = random_soup(100, 2);
  const UniformGrid g = build_grid("grid:res=4096", s.prims);
  const auto r = g.resolution();
  EXPECT_LE(size_t(r[0]) * r[1] * r[2], kMinCellCap);
  EXPECT_EQ(g.stats().nodes, size_t(r[0]) * r[1] * r[2]);
}

}  // namespace
}  // namespace penumbra::test
