// The 4-lane block test must return exactly what the scalar watertight test returns when run
// over the same triangles: same primitive, and t, u, v to the bit (the least (t, id): hit.h).
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <vector>

#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/triangle_blocks.h"
#include "penumbra/core/rng.h"
#include "penumbra/geometry/triangle.h"

namespace penumbra {
namespace {

/// The scalar reference: the triangles in order, each hit shrinking the interval (to the same
/// t for a lower id: hit.h, tie_bound).
bool scalar_closest(const PrimitiveSet& prims, std::span<const uint32_t> ids, const PreparedRay& pr,
                    Hit& hit) {
  bool found = false;
  for (uint32_t id : ids) {
    const Vec3* v = prims.triangle(id);
    float t, u, w;
    if (intersect_triangle(pr, v[0], v[1], v[2], pr.ray.tmin, tie_bound(hit, id), t, u, w)) {
      hit = {t, u, w, id};
      found = true;
    }
  }
  return found;
}

/// The block test of the leaf of `ids` at block `first` against the scalar reference on `pr`
/// over (tmin, tmax), closest and any hit, to the bit (`it` names the case); returns the
/// reference's hit (not valid() where there is none).
Hit expect_as_scalar(const TriangleBlocks& blocks, uint32_t first, const PrimitiveSet& prims,
                     std::span<const uint32_t> ids, const PreparedRay& pr, float tmax, int it) {
  Hit expected, got;
  expected.t = got.t = tmax;
  const bool e = scalar_closest(prims, ids, pr, expected);
  const auto n = uint32_t(ids.size());
  EXPECT_EQ(blocks.intersect<false>(BlockRay(pr), first, n, got), e) << "iteration " << it;
  EXPECT_EQ(got.prim, expected.prim) << "iteration " << it;
  EXPECT_EQ(std::bit_cast<uint32_t>(got.t), std::bit_cast<uint32_t>(expected.t)) << it;
  EXPECT_EQ(std::bit_cast<uint32_t>(got.u), std::bit_cast<uint32_t>(expected.u)) << it;
  EXPECT_EQ(std::bit_cast<uint32_t>(got.v), std::bit_cast<uint32_t>(expected.v)) << it;
  Hit any;
  any.t = tmax;
  EXPECT_EQ(blocks.intersect<true>(BlockRay(pr), first, n, any), e) << "iteration " << it;
  EXPECT_EQ(expected.valid(), e) << "iteration " << it;
  return expected;
}

/// A leaf of the triangles of `mesh` (three vertices each, in order), its ids in decreasing
/// order (not id order, so that lane and block order meet the highest id first), filled at block
/// `first` (behind unused blocks when not 0).
struct Leaf {
  PrimitiveSet prims;
  std::vector<uint32_t> ids;
  TriangleBlocks blocks;
};
Leaf make_leaf(const TriangleMesh& mesh, uint32_t first) {
  Leaf leaf;
  leaf.prims.add_mesh(mesh, Transform(), 0);
  const auto n = uint32_t(mesh.indices.size() / 3);
  leaf.ids.resize(n);
  std::vector<PrimRef> refs(n);
  for (uint32_t i = 0; i < n; ++i) leaf.ids[i] = n - 1 - i, refs[i].id = leaf.ids[i];
  leaf.blocks.resize(TriangleBlocks::blocks_for(n) + first);
  leaf.blocks.fill(first, leaf.prims, refs);
  return leaf;
}

TEST(TriangleBlocks, MatchTheScalarTestBitForBit) {
  // Leaves of 1..12 triangles (one to three blocks, the last padded; with AVX a pair of blocks
  // is tested as eight lanes, a last odd block as four): random triangles, and
  // triangles sharing an edge or a vertex with rays aimed at it (where rounding decides), at
  // small and large scales, plus degenerate ones; random ray intervals.
  Pcg32 rng(11, 2);
  size_t hits = 0, any_hits = 0;
  for (int it = 0; it < 20000; ++it) {
    const float scale = it % 3 == 0 ? 1e-3f : (it % 3 == 1 ? 1.0f : 1e4f);
    const auto rv = [&] {
      return Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * scale;
    };
    const uint32_t n = 1 + rng.next_bounded(12);
    const Vec3 shared0 = rv(), shared1 = rv();
    TriangleMesh mesh;
    for (uint32_t i = 0; i < n; ++i) {
      const Vec3 a = it % 2 ? rv() : shared0;
      const Vec3 c = i == 3 ? shared0 + (shared1 - shared0) * 0.5f : rv();  // degenerate at 3
      for (const Vec3& p : {a, shared1, c}) mesh.positions.push_back(p);
      for (uint32_t k = 0; k < 3; ++k) mesh.indices.push_back(3 * i + k);
    }
    const Leaf leaf = make_leaf(mesh, 1);  // at an offset, behind an unused block

    const float w = rng.next_float();
    const Vec3 target = it % 4 == 0 ? shared0 : shared0 * w + shared1 * (1.0f - w);
    Ray ray{target + (rv() - Vec3(0.5f * scale)) * 2.0f, {}};
    ray.d = target - ray.o;
    if (it % 5 == 0) ray.tmin = 0.5f * rng.next_float();
    const float tmax = it % 7 == 0 ? 0.5f + rng.next_float() : kInfinity;
    const bool e =
        expect_as_scalar(leaf.blocks, 1, leaf.prims, leaf.ids, PreparedRay(ray), tmax, it).valid();
    hits += e;
    any_hits += e && n > 4;
  }
  // The rays aim at the shared edge, so most must hit something (and many in second blocks).
  EXPECT_GT(hits, 10000u);
  EXPECT_GT(any_hits, 4000u);
}

TEST(TriangleBlocks, CopiesOfATriangleGiveTheLowestIdInEveryLane) {
  // A leaf of 1..12 copies of one triangle, their ids in decreasing order (so lane order and
  // block order both meet the highest id first): every ray through it gets the lowest id, at
  // the one t all copies share, as a hit in the same place before the test would decide.
  Pcg32 rng(12, 7);
  for (int it = 0; it < 2000; ++it) {
    const uint32_t n = 1 + rng.next_bounded(12);
    const auto rv = [&] { return Vec3(rng.next_float(), rng.next_float(), rng.next_float()); };
    const Vec3 a = rv(), b = rv(), c = rv();
    TriangleMesh mesh;
    for (uint32_t i = 0; i < n; ++i) {
      for (const Vec3& p : {a, b, c}) mesh.positions.push_back(p);
      for (uint32_t k = 0; k < 3; ++k) mesh.indices.push_back(3 * i + k);
    }
    const Leaf leaf = make_leaf(mesh, 0);
    const TriangleBlocks& blocks = leaf.blocks;
    Ray ray{rv() * 3.0f - Vec3(1.0f), {}};
    ray.d = (a + b + c) * (1.0f / 3.0f) - ray.o;
    const PreparedRay pr(ray);
    const Hit h = expect_as_scalar(blocks, 0, leaf.prims, leaf.ids, pr, kInfinity, it);
    ASSERT_TRUE(h.valid()) << "iteration " << it;
    EXPECT_EQ(h.prim, 0u) << "iteration " << it;
    // With a hit of a lower id already at that t, the leaf leaves it be; with a higher id, the
    // leaf's lowest replaces it.
    Hit lower = h, higher = h;
    lower.prim = 0, higher.prim = n;
    if (n > 1) {
      Hit got = lower;
      EXPECT_FALSE(blocks.intersect<false>(BlockRay(pr), 0, n, got)) << "iteration " << it;
      EXPECT_EQ(got.prim, 0u);
    }
    Hit got = higher;
    EXPECT_TRUE(blocks.intersect<false>(BlockRay(pr), 0, n, got)) << "iteration " << it;
    EXPECT_EQ(got.prim, 0u) << "iteration " << it;
  }
}

TEST(TriangleBlocks, MatchTheScalarTestForRaysLeavingASurface) {
  // Rays starting on one of the leaf's triangles (the origin a float barycentric combination of
  // its vertices, so within rounding of its plane), as a path tracer's bounce and shadow rays
  // do: the computed t of that triangle is then near zero, and the bound on t
  // (triangle_t_error) decides whether it is hit: rejected where t lies within the bound,
  // accepted where the rounded origin lies far enough off the plane for a true hit. The block
  // test must decide as the scalar one does, to the bit, both ways.
  Pcg32 rng(23, 5);
  size_t rejected = 0, accepted = 0;
  for (int it = 0; it < 20000; ++it) {
    const float scale = it % 3 == 0 ? 1e-3f : (it % 3 == 1 ? 1.0f : 1e4f);
    const Vec3 offset = Vec3(1.0f + rng.next_float(), -2.0f, 3.0f) * (scale * 10.0f);
    const auto rv = [&] {
      return offset + Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * scale;
    };
    const uint32_t n = 1 + rng.next_bounded(12);
    TriangleMesh mesh;
    for (uint32_t i = 0; i < 3 * n; ++i) mesh.positions.push_back(rv());
    for (uint32_t i = 0; i < 3 * n; ++i) mesh.indices.push_back(i);
    PrimitiveSet prims;
    prims.add_mesh(mesh, Transform(), 0);
    std::vector<uint32_t> ids(n);
    std::vector<PrimRef> refs(n);
    for (uint32_t i = 0; i < n; ++i) ids[i] = i, refs[i].id = i;
    TriangleBlocks blocks;
    blocks.resize(TriangleBlocks::blocks_for(n));
    blocks.fill(0, prims, refs);

    const uint32_t from = rng.next_bounded(n);
    const Vec3* v = prims.triangle(from);
    const float b1 = rng.next_float(), b2 = rng.next_float() * (1.0f - b1);
    Ray ray{v[0] * (1.0f - b1 - b2) + v[1] * b1 + v[2] * b2, {}};
    ray.d = Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f);
    const Hit expected = expect_as_scalar(blocks, 0, prims, ids, PreparedRay(ray), kInfinity, it);
    // Where the rounded origin lies in front of the triangle it leaves (its exact t, in double,
    // above zero), the test decides near t = 0 by the bound: count both of its answers.
    const auto dv = [](Vec3 p) { return std::array<double, 3>{p.x, p.y, p.z}; };
    // Exact in float (Sterbenz: each coordinate's values lie within a factor of 2).
    const auto e1 = dv(v[1] - v[0]), e2 = dv(v[2] - v[0]);
    const std::array<double, 3> nrm = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                       e1[0] * e2[1] - e1[1] * e2[0]};
    const auto o = dv(ray.o), p0 = dv(v[0]), d = dv(ray.d);
    double num = 0, den = 0;
    for (int a = 0; a < 3; ++a) num += (p0[a] - o[a]) * nrm[a], den += d[a] * nrm[a];
    if (den != 0 && num / den > 0) ++(expected.prim == from ? accepted : rejected);
  }
  EXPECT_GT(rejected, 1000u);
  EXPECT_GT(accepted, 100u);
}

TEST(TriangleBlocks, PaddingLanesAreNeverHit) {
  // fill() with kNoPrim padding: a ray through where padding "would be" (the origin of the
  // NaN lanes) hits nothing, and the real lane keeps its id.
  TriangleMesh mesh;
  mesh.positions = {{-1, -1, 1}, {1, -1, 1}, {0, 1, 1}};
  mesh.indices = {0, 1, 2};
  PrimitiveSet prims;
  prims.add_mesh(mesh, Transform(), 0);
  const uint32_t ids[2] = {kNoPrim, 0};
  TriangleBlocks blocks;
  blocks.resize(1);
  blocks.fill(0, prims, std::span<const uint32_t>(ids));
  ASSERT_EQ(blocks.size(), 1u);
  Hit hit;
  const PreparedRay hits(Ray{{0, 0, 0}, {0, 0, 1}});
  ASSERT_TRUE(blocks.intersect<false>(BlockRay(hits), 0, 2, hit));
  EXPECT_EQ(hit.prim, 0u);
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  Hit miss;
  const PreparedRay misses(Ray{{5, 5, 0}, {0, 0, 1}});
  EXPECT_FALSE(blocks.intersect<false>(BlockRay(misses), 0, 4, miss));
  EXPECT_FALSE(miss.valid());
}

// The counting test counts the triangles of the blocks it tests, padding left out: all of a
// leaf in a closest-hit test, and in an any-hit test only those up to the block (or pair of
// blocks, as eight lanes) that holds the first hit.
TEST(TriangleBlocks, CountTheTrianglesOfTheBlocksTested) {
  // Eleven parallel triangles along z, the third of them the only one a ray at x = 0 hits.
  TriangleMesh mesh;
  for (int i = 0; i < 11; ++i) {
    const float x = i == 2 ? 0.0f : 10.0f + float(i);
    const auto base = uint32_t(mesh.positions.size());
    mesh.positions.push_back({x - 1, -1, float(i + 1)});
    mesh.positions.push_back({x + 1, -1, float(i + 1)});
    mesh.positions.push_back({x, 1, float(i + 1)});
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
  }
  PrimitiveSet prims;
  prims.add_mesh(mesh, Transform(), 0);
  std::vector<uint32_t> ids(11);
  for (uint32_t i = 0; i < 11; ++i) ids[i] = i;
  TriangleBlocks blocks;
  blocks.resize(3);
  blocks.fill(0, prims, std::span<const uint32_t>(ids));
  const PreparedRay through(Ray{{0, 0, 0}, {0, 0, 1}});
  const PreparedRay past(Ray{{-50, 0, 0}, {0, 0, 1}});
  for (const PreparedRay* pr : {&through, &past}) {
    TraversalCost closest;
    Hit hit;
    EXPECT_EQ(blocks.intersect<false>(BlockRay(*pr), 0, 11, hit, CostCounter{&closest}),
              pr == &through);
    EXPECT_EQ(closest.prims, 11u);
  }
  // The hit is in the first block: four lanes, or the first pair's eight.
  TraversalCost any;
  Hit hit;
  EXPECT_TRUE(blocks.intersect<true>(BlockRay(through), 0, 11, hit, CostCounter{&any}));
  EXPECT_EQ(any.prims, TriangleBlocks::kPairs ? 8u : 4u);
  TraversalCost none;
  EXPECT_FALSE(blocks.intersect<true>(BlockRay(past), 0, 11, hit, CostCounter{&none}));
  EXPECT_EQ(none.prims, 11u);
  EXPECT_EQ(any.nodes + none.nodes, 0u);
}

}  // namespace
}  // namespace penumbra
