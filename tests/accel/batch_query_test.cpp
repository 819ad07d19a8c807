/// Batch queries (Accelerator::intersect_batch, occluded_batch) against the single-ray ones: for
/// every registered structure, and for those with an `interleave` parameter (the wide BVHs)
/// with it forced on and off, every ray of batches of every size gets the same bits, untraceable
/// and shadow rays among them.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

/// mixed_rays over `prims`, with a finite tmax on every seventh (shadow rays) and untraceable
/// rays (a zero direction, a NaN origin) spread among them.
std::vector<Ray> batch_rays(const PrimitiveSet& prims, size_t n, uint64_t seed) {
  std::vector<Ray> rays = mixed_rays(prims, n, seed);
  for (size_t i = 0; i < rays.size(); i += 7) rays[i].tmax = 0.3f + float(i % 5);
  for (size_t i = 3; i < rays.size(); i += 101) rays[i].d = Vec3(0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 5; i < rays.size(); i += 211) rays[i].o.x = nan;
  return rays;
}

/// Counts the rays whose batch answers differ in any bit from the single queries', the rays cut
/// into batches of 0, 1, 7, 8, 9, 64 and 200 rays (that one coherent), then one of the rest.
size_t batch_differences(const Accelerator& accel, const std::vector<Ray>& rays) {
  std::vector<Hit> single(rays.size());
  std::vector<uint8_t> single_blocked(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    accel.intersect(rays[i], single[i]);
    single_blocked[i] = accel.occluded(rays[i]);
  }
  // Records the batch must overwrite.
  Hit stale;
  stale.t = -1.0f, stale.u = 7.0f, stale.v = 7.0f, stale.prim = 12345, stale.instance = 3;
  std::vector<Hit> hits(rays.size(), stale);
  std::vector<uint8_t> blocked(rays.size(), 2);
  const std::span<const Ray> all(rays);
  size_t begin = 0;
  const size_t sizes[] = {0, 1, 7, 8, 9, 64, 200, rays.size()};
  for (size_t k = 0; k < std::size(sizes); ++k) {
    const size_t n = std::min(sizes[k], rays.size() - begin);
    const BatchOrder order = k == 6 ? BatchOrder::kCoherent : BatchOrder::kIncoherent;
    accel.intersect_batch(all.subspan(begin, n), std::span<Hit>(hits).subspan(begin, n), order);
    accel.occluded_batch(all.subspan(begin, n), std::span<uint8_t>(blocked).subspan(begin, n),
                         order);
    begin += n;
  }
  const auto bits = [](float x) { return std::bit_cast<uint32_t>(x); };
  size_t differ = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Hit& a = single[i];
    const Hit& b = hits[i];
    differ += bits(a.t) != bits(b.t) || bits(a.u) != bits(b.u) || bits(a.v) != bits(b.v) ||
              a.prim != b.prim || a.instance != b.instance || single_blocked[i] != blocked[i];
  }
  return differ;
}

/// The structure itself, and with interleave=on and =off where it takes that parameter.
std::vector<std::string> variants(const std::string& name) {
  std::vector<std::string> out = {name};
  const std::string sep = name.find(':') == std::string::npos ? ":" : ",";
  for (const char* mode : {"interleave=on", "interleave=off"}) {
    try {
      make_accelerator(name + sep + mode);
      out.push_back(name + sep + mode);
    } catch (const Error&) {
    }
  }
  return out;
}

class BatchQueries : public ::testing::TestWithParam<std::string> {};

TEST_P(BatchQueries, AnswerAsSingleQueriesBitForBit) {
  std::vector<TestScene> scenes;
  scenes.push_back(random_soup(1500, 31));     // triangles only: the SIMD leaf blocks
  scenes.push_back(mixed_shapes(32));          // spheres and quads: the per-primitive leaves
  scenes.push_back(room_with_boxes(40, 33));   // axis-aligned: rays along box planes
  scenes.push_back(moving_soup(600, 34));      // moving: rays with times
  for (const std::string& spec : variants(GetParam())) {
    for (size_t s = 0; s < scenes.size(); ++s) {
      auto accel = make_accelerator(spec);
      accel->build(scenes[s].prims);
      std::vector<Ray> rays = batch_rays(scenes[s].prims, 3000, 40 + s);
      if (s == 3) set_random_times(rays, 50);
      EXPECT_EQ(batch_differences(*accel, rays), 0u) << spec << " on " << scenes[s].name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Registry, BatchQueries, ::testing::ValuesIn(structure_names()),
                         [](const auto& info) { return structure_test_name(info.param); });

TEST(BatchQueries, InterleavingIsOnByParameterOrForStructuresBeyondTheCaches) {
  const TestScene soup = random_soup(500, 35);
  const auto interleaved = [&](const std::string& spec) {
    auto accel = make_accelerator(spec);
    accel->build(soup.prims);
    return extra_stat(*accel, "interleaved batches");
  };
  EXPECT_EQ(interleaved("bvh"), 0.0);  // auto: 500 triangles stay in the caches
  EXPECT_EQ(interleaved("bvh:interleave=on"), 1.0);
  EXPECT_EQ(interleaved("bvh:interleave=off"), 0.0);
  EXPECT_EQ(interleaved("bvh4:interleave=on"), 1.0);
  EXPECT_THROW(make_accelerator("bvh:interleave=2"), Error);
}

}  // namespace
}  // namespace penumbra::test
