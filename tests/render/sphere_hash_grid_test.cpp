// SPPM's hash grid of visible points: every sphere containing a point is among its candidates.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "penumbra/core/rng.h"
#include "penumbra/render/photon/sphere_hash_grid.h"

namespace penumbra {
namespace {

/// Random spheres (radii spread over a factor `spread`) and random query points; the candidates
/// of each point must contain every sphere that contains it (checked by brute force).
void check_superset(int spheres, float spread, uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<Vec3> c(static_cast<size_t>(spheres));
  std::vector<float> r(static_cast<size_t>(spheres));
  for (int i = 0; i < spheres; ++i) {
    c[size_t(i)] = {rng.next_float() * 10, rng.next_float() * 10, rng.next_float() * 2};
    // Some spheres are switched off (radius 0), as pixels without a visible point are.
    r[size_t(i)] = i % 7 == 3 ? 0.0f : 0.05f + rng.next_float() * 0.05f * spread;
  }
  SphereHashGrid grid;
  grid.build(c, r);
  int inside = 0;
  double volume = 0;  // of the spheres, for the containments to expect
  for (float ri : r) volume += 4.0 / 3.0 * 3.14159265 * double(ri) * ri * ri;
  const double expected = 20000.0 * volume / 200.0;
  for (int q = 0; q < 20000; ++q) {
    const Vec3 p{rng.next_float() * 10, rng.next_float() * 10, rng.next_float() * 2};
    const auto [b, e] = grid.candidates(p);
    std::vector<uint32_t> cand(b, e);
    std::sort(cand.begin(), cand.end());
    EXPECT_TRUE(std::adjacent_find(cand.begin(), cand.end()) == cand.end())
        << "a sphere listed twice in one bucket";
    for (int i = 0; i < spheres; ++i) {
      const Vec3 d = p - c[size_t(i)];
      if (r[size_t(i)] > 0 && dot(d, d) <= r[size_t(i)] * r[size_t(i)]) {
        ++inside;
        EXPECT_TRUE(std::binary_search(cand.begin(), cand.end(), uint32_t(i)))
            << "sphere " << i << " contains the point but is not a candidate";
      }
      if (r[size_t(i)] == 0) {
        EXPECT_FALSE(std::binary_search(cand.begin(), cand.end(), uint32_t(i)));
      }
    }
  }
  // The test exercised containment about as often as the volumes say.
  if (expected > 100) {
    EXPECT_GT(inside, 0.5 * expected);
  }
}

TEST(SphereHashGrid, CandidatesContainEverySphereHoldingThePoint) {
  check_superset(2000, 1.0f, 1);
  check_superset(500, 20.0f, 2);  // radii over a factor 20: cells set by the largest
  check_superset(1, 1.0f, 3);
}

TEST(SphereHashGrid, EmptyAndOutsideGiveNoCandidates) {
  SphereHashGrid grid;
  grid.build({}, {});
  auto [b, e] = grid.candidates({0, 0, 0});
  EXPECT_EQ(b, e);
  grid.build({{0, 0, 0}}, {0.0f});  // every sphere off
  std::tie(b, e) = grid.candidates({0, 0, 0});
  EXPECT_EQ(b, e);
  grid.build({{0, 0, 0}}, {1.0f});
  std::tie(b, e) = grid.candidates({5, 0, 0});
  EXPECT_EQ(b, e);
  std::tie(b, e) = grid.candidates({0.5f, 0, 0});
  ASSERT_EQ(e - b, 1);
  EXPECT_EQ(*b, 0u);
}

// Candidate lists stay short: a bucket holds the spheres of about one cell, so a point in a
// uniform field of spheres of equal radius sees a few tens of candidates, not all of them.
TEST(SphereHashGrid, CandidateListsAreShort) {
  Pcg32 rng(9);
  std::vector<Vec3> c;
  std::vector<float> r;
  for (int i = 0; i < 20000; ++i) {
    c.push_back({rng.next_float() * 100, rng.next_float() * 100, 0.0f});
    r.push_back(0.2f);
  }
  SphereHashGrid grid;
  grid.build(c, r);
  size_t total = 0;
  for (int q = 0; q < 1000; ++q) {
    const auto [b, e] = grid.candidates({rng.next_float() * 100, rng.next_float() * 100, 0.0f});
    total += size_t(e - b);
  }
  // 20000 spheres on 100 x 100 with cells 0.4 wide: each is listed in the 2 x 2 cells of the
  // plane z = 0 that its box overlaps (and in 4 of the layer above, which its box touches), so
  // a cell of the plane lists 1.28 spheres; 40000 buckets for 125000 occupied cells bring in
  // about 3.1 x 1.28 = 4 more through collisions: 5.3 expected; a grid that lists everything
  // would give 20000.
  EXPECT_LT(double(total) / 1000.0, 6.0);
}

}  // namespace
}  // namespace penumbra
