/// Tests of the pre-splitting of large triangles (bvh:presplit=F, accel/build/presplit.h): the
/// pieces of a triangle cover all of it and stay inside its box, the budget holds, the result
/// does not depend on the thread count, and the split tree does less work on large triangles.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <vector>

#include "penumbra/accel/build/presplit.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/geometry/triangle_mesh.h"

#include "test_scenes.h"

namespace penumbra {
namespace {

using test::TestScene;

using test::large_triangles;

TEST(Presplit, PiecesCoverTheWholeTriangleInsideItsBox) {
  const TestScene s = large_triangles(300, 700, 1);
  PrimRefs refs = make_prim_refs(s.prims);
  const size_t n = refs.refs.size();
  presplit_refs(s.prims, refs, 2.0);
  EXPECT_GT(refs.refs.size(), n + n / 2);  // most of the budget is used
  EXPECT_LE(refs.refs.size(), 3 * n);
  std::map<uint32_t, std::vector<Bounds3>> pieces;
  for (const PrimRef& r : refs.refs) pieces[r.id].push_back(r.bounds());
  ASSERT_EQ(pieces.size(), n);  // every triangle keeps at least one reference
  Bounds3 centroids;
  for (const PrimRef& r : refs.refs) centroids.extend(r.centroid2());
  EXPECT_EQ(refs.centroid_bounds, centroids);
  Pcg32 rng(9, 1);
  size_t split = 0;
  for (const auto& [id, boxes] : pieces) {
    const Bounds3 whole = s.prims.prim_bounds(id);
    split += boxes.size() > 1;
    for (const Bounds3& b : boxes) {
      EXPECT_FALSE(b.empty()) << id;
      EXPECT_TRUE(whole.contains(b.lo) && whole.contains(b.hi)) << id;
    }
    // Vertices, edge midpoints and random points of the triangle: each in some piece.
    const Vec3* v = s.prims.triangle(id);
    std::vector<Vec3> points = {
        v[0], v[1], v[2], (v[0] + v[1]) * 0.5f, (v[1] + v[2]) * 0.5f, (v[2] + v[0]) * 0.5f};
    for (int k = 0; k < 200; ++k)
      points.push_back(test::point_on(s.prims, id, rng.next_float(), rng.next_float()));
    for (const Vec3& p : points) {
      bool covered = false;
      for (const Bounds3& b : boxes) covered = covered || b.contains(p);
      ASSERT_TRUE(covered) << "triangle " << id << ": point " << p.x << " " << p.y << " " << p.z
                           << " in none of its " << boxes.size() << " pieces";
    }
  }
  EXPECT_GT(split, 250u);  // the large triangles are the ones split
}

TEST(Presplit, SameReferencesAtEveryThreadCount) {
  const TestScene s = large_triangles(20000, 20000, 2);
  std::vector<PrimRef> reference;
  for (int threads : {1, 2, 3}) {
    const ThreadLimit limit(threads);
    PrimRefs refs = make_prim_refs(s.prims);
    presplit_refs(s.prims, refs, 0.7);
    if (threads == 1) {
      reference.assign(refs.refs.begin(), refs.refs.end());
      continue;
    }
    ASSERT_EQ(refs.refs.size(), reference.size()) << threads;
    EXPECT_EQ(std::memcmp(refs.refs.data(), reference.data(), reference.size() * sizeof(PrimRef)),
              0)
        << threads << " threads";
  }
}

TEST(Presplit, NoBudgetNoChangeAndBadInputIsRefused) {
  const TestScene s = large_triangles(100, 0, 3);
  PrimRefs refs = make_prim_refs(s.prims);
  const std::vector<PrimRef> before(refs.refs.begin(), refs.refs.end());
  presplit_refs(s.prims, refs, 0.0);
  ASSERT_EQ(refs.refs.size(), before.size());
  EXPECT_EQ(std::memcmp(refs.refs.data(), before.data(), before.size() * sizeof(PrimRef)), 0);
  EXPECT_THROW(presplit_refs(s.prims, refs, -0.5), Error);
  EXPECT_THROW(presplit_refs(s.prims, refs, 5.0), Error);
  const TestScene mixed = test::mixed_shapes(4);  // spheres and quads are not split
  PrimRefs mixed_refs = make_prim_refs(mixed.prims);
  EXPECT_THROW(presplit_refs(mixed.prims, mixed_refs, 1.0), Error);
  EXPECT_NO_THROW(make_accelerator("bvh:presplit=1")->build(mixed.prims));  // skipped there

  EXPECT_NO_THROW(make_accelerator("bvh4:presplit=0.3"));
  EXPECT_NO_THROW(make_accelerator("bvh:presplit=4,collapse=sah,nodes=compressed"));
  for (const char* bad : {"bvh:presplit=-1", "bvh:presplit=4.5", "bvh:width=2,presplit=1"})
    EXPECT_THROW(make_accelerator(bad), Error) << bad;
}

// The point of it: on large triangles the split tree tests far fewer triangles per ray, visits
// no more nodes, and its SAH cost is lower; a leaf never tests one triangle twice.
TEST(Presplit, LargeTrianglesCostFewerTestsPerRay) {
  const TestScene s = large_triangles(2000, 2000, 4);
  // Without spatial splits on either side: the pre-split alone against object splits.
  auto plain = make_accelerator("bvh:spatial=0"),
       split = make_accelerator("bvh:presplit=2,spatial=0");
  plain->build(s.prims);
  split->build(s.prims);
  EXPECT_GT(split->stats().prim_refs, plain->stats().prim_refs * 2);
  const auto rays = test::mixed_rays(s.prims, 20000, 5);
  TraversalCost a, b;
  test::trace_both(*plain, *split, rays, a, b);

  EXPECT_LT(double(b.prims), 0.6 * double(a.prims));
  EXPECT_LT(b.nodes, a.nodes);
  const auto sah = [](const Accelerator& acc) { return test::extra_stat(acc, "sah_cost"); };
  EXPECT_LT(sah(*split), sah(*plain));
}

}  // namespace
}  // namespace penumbra
