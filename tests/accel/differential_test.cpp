/// Every registered structure against `brute` on generated scene families, static and moving:
/// closest hits (the same primitive, t and (u, v), bit for bit), occlusion with infinite and
/// finite tmax. The
/// structures come from the registry, so a new structure is tested by registering it.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "penumbra/accel/registry.h"
#include "penumbra/core/parallel.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

/// A scene with its rays and brute-force closest hits.
struct Case {
  TestScene scene;
  std::vector<Ray> rays;
  std::vector<Hit> reference;
};

/// Brute-force closest hits, in parallel.
std::vector<Hit> brute_hits(const PrimitiveSet& prims, const std::vector<Ray>& rays) {
  auto brute = make_accelerator("brute");
  brute->build(prims);
  std::vector<Hit> hits(rays.size());
  parallel_for_range(
      rays.size(),
      [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) brute->intersect(rays[i], hits[i]);
      },
      64);
  return hits;
}

/// The cases of a scene family (built once per process, shared by every structure): each family
/// has at least 100,000 rays in total.
const std::vector<Case>& family(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::vector<Case>> cache;
  const std::lock_guard lock(mutex);
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  std::vector<std::pair<TestScene, size_t>> scenes;
  if (name == "soup") scenes.emplace_back(random_soup(1500, 11), 100'000);
  if (name == "grid") scenes.emplace_back(coplanar_grid(20, 20), 100'000);
  if (name == "room") scenes.emplace_back(room_with_boxes(60, 12), 100'000);
  if (name == "thin") scenes.emplace_back(thin_and_large(13), 100'000);
  if (name == "mixed") scenes.emplace_back(mixed_shapes(14), 100'000);
  if (name == "degenerate") scenes.emplace_back(degenerate_triangles(15), 100'000);
  if (name == "coincident") {
    scenes.emplace_back(coincident_surfaces(21, false), 60'000);
    scenes.emplace_back(coincident_surfaces(22, true), 40'000);
  }
  // Moving geometry (rays with times): every structure must bound primitives over the whole
  // time interval and test them at the ray's time.
  if (name == "moving_soup") scenes.emplace_back(moving_soup(1000, 16), 100'000);
  if (name == "moving_shapes") scenes.emplace_back(moving_shapes(17), 100'000);
  if (name == "static_and_moving") scenes.emplace_back(static_and_moving(18), 100'000);
  // Extreme magnitudes: the same mixed scene from 1e-10 to 1e10 in size (the accepted range,
  // kMinSceneExtent to kMaxCoordinate), and far from the origin; a scene whose extent
  // overflows float.
  if (name == "scaled") {
    const TestScene base = mixed_shapes(19);
    for (const float s : {1e-10f, 1e-5f, 1e5f, 1e10f})
      scenes.emplace_back(scaled(base, s, Vec3(0.0f)), 20'000);
    scenes.emplace_back(scaled(base, 1.0f, Vec3(1e6f, -2e6f, 3e6f)), 20'000);
  }
  // Rays from the ordinary part: the extent of the whole scene is not finite.
  std::optional<TestScene> ray_source;
  if (name == "float_range") {
    scenes.emplace_back(float_range_extent(20), 100'000);
    ray_source = random_soup(500, 20);
  }
  if (name == "torus") {  // the 50k-triangle mesh gets fewer rays: brute costs O(N) per ray
    scenes.emplace_back(torus(20, 25), 60'000);
    scenes.emplace_back(torus(50, 40), 36'000);
    scenes.emplace_back(torus(250, 100), 4'000);
  }
  std::vector<Case> cases;
  uint64_t seed = 100;
  for (auto& [scene, n] : scenes) {
    Case c{std::move(scene), {}, {}};
    c.rays = mixed_rays(ray_source ? ray_source->prims : c.scene.prims, n, seed++);
    if (c.scene.prims.has_motion()) set_random_times(c.rays, seed);
    c.reference = brute_hits(c.scene.prims, c.rays);
    cases.push_back(std::move(c));
  }
  return cache.emplace(name, std::move(cases)).first->second;
}

std::string describe(const Ray& r) {
  return fmt::format("o=({:a}, {:a}, {:a}) d=({:a}, {:a}, {:a})", r.o.x, r.o.y, r.o.z, r.d.x, r.d.y,
                     r.d.z);
}

/// Distance along `r` to primitive `id`'s plane (triangles, quads) or surface (spheres) in double
/// precision, at the ray's time: the geometry's answer, free of the float test's rounding.
double exact_t(const PrimitiveSet& prims, uint32_t id, const Ray& r, double t_hint) {
  const auto d3 = [](Vec3 v) { return std::array<double, 3>{v.x, v.y, v.z}; };
  const auto sub = [](std::array<double, 3> a, std::array<double, 3> b) {
    return std::array<double, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  };
  const auto dotd = [](std::array<double, 3> a, std::array<double, 3> b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  const auto crossd = [](std::array<double, 3> a, std::array<double, 3> b) {
    return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                 a[0] * b[1] - a[1] * b[0]};
  };
  switch (prims.kind(id)) {
    case PrimKind::kTriangle: {
      Vec3 v[3];
      prims.triangle_at(id, r.time, v);
      const auto n = crossd(sub(d3(v[1]), d3(v[0])), sub(d3(v[2]), d3(v[0])));
      return dotd(n, sub(d3(v[0]), d3(r.o))) / dotd(n, d3(r.d));
    }
    case PrimKind::kQuad: {
      const QuadData q = prims.quad_at(id, r.time);
      const auto n = crossd(d3(q.e1), d3(q.e2));
      return dotd(n, sub(d3(q.p), d3(r.o))) / dotd(n, d3(r.d));
    }
    default:
      return t_hint;  // the sphere test already works in double
  }
}

/// Whether two hits are the same, bit for bit: primitive, t and (u, v).
bool same_hit(const Hit& a, const Hit& b) {
  const auto bits = [](float x) { return std::bit_cast<uint32_t>(x); };
  return a.prim == b.prim && bits(a.t) == bits(b.t) && bits(a.u) == bits(b.u) &&
         bits(a.v) == bits(b.v);
}

/// Checks closest hit and both occlusion queries of every ray; returns failure descriptions.
std::vector<std::string> check(const Accelerator& accel, const Case& c) {
  const PrimitiveSet& prims = c.scene.prims;
  std::vector<std::string> errors(c.rays.size());
  parallel_for_range(
      c.rays.size(),
      [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
          const Ray& ray = c.rays[i];
          const Hit& ref = c.reference[i];
          Hit got;
          const bool hit = accel.intersect(ray, got);
          std::string& err = errors[i];
          if (hit != ref.valid() || got.valid() != ref.valid()) {
            err = fmt::format("closest: hit {} (prim {}, t {}) but brute {} (prim {}, t {})", hit,
                              got.prim, got.t, ref.valid(), ref.prim, ref.t);
          } else if (hit && !same_hit(got, ref)) {
            // The closest hit is the least (t, id) over the primitives hit, and each primitive's
            // t does not depend on the order of tests (hit.h, tie_bound, cull_bound): every
            // structure must return brute's hit exactly, on coincident surfaces too.
            err = fmt::format("closest: prim {} at t {:a} (u {:a}, v {:a}) but brute prim {} at t "
                              "{:a} (u {:a}, v {:a})",
                              got.prim, got.t, got.u, got.v, ref.prim, ref.t, ref.u, ref.v);
          }
          if (err.empty() && accel.occluded(ray) != ref.valid())
            err = fmt::format("occluded(tmax=inf) = {} but brute hits: {}", !ref.valid(),
                              ref.valid());
          // Finite tmax just before and just after the closest hit (or anywhere when none).
          Ray shadow = ray;
          shadow.tmax = ref.valid() ? ref.t * (i % 2 ? 1.001f : 0.999f) : 0.5f + float(i % 7);
          const bool expect = ref.valid() && ref.t < shadow.tmax;
          // Only where the float test and the exact geometry agree on the side of tmax: grazing
          // rays from near a surface can make the float t err by more than the 0.1% margin.
          const bool clear =
              !ref.valid() || (exact_t(prims, ref.prim, ray, ref.t) < shadow.tmax) == expect;
          if (err.empty() && clear && accel.occluded(shadow) != expect)
            err = fmt::format("occluded(tmax={}) = {}, expected {} (brute t {})", shadow.tmax,
                              !expect, expect, ref.t);
          if (!err.empty()) err += "; ray " + describe(ray);
        }
      },
      64);
  std::vector<std::string> out;
  for (auto& e : errors)
    if (!e.empty()) out.push_back(std::move(e));
  return out;
}

class AccelDifferential : public ::testing::TestWithParam<std::string> {
 protected:
  void run_family(const std::string& name) {
    size_t rays = 0;
    for (const Case& c : family(name)) {
      auto accel = make_accelerator(GetParam());
      accel->build(c.scene.prims);
      const auto errors = check(*accel, c);
      rays += c.rays.size();
      EXPECT_EQ(errors.size(), 0u)
          << GetParam() << " on " << c.scene.name << " (" << c.scene.prims.size()
          << " prims): " << errors.size() << " of " << c.rays.size() << " rays differ from brute";
      for (size_t k = 0; k < std::min<size_t>(errors.size(), 5); ++k) ADD_FAILURE() << errors[k];
    }
    EXPECT_GE(rays, 100'000u);
  }
};

TEST_P(AccelDifferential, RandomTriangleSoup) {
  run_family("soup");
}
TEST_P(AccelDifferential, GridOfCoplanarQuads) {
  run_family("grid");
}
TEST_P(AccelDifferential, AxisAlignedRoomWithBoxes) {
  run_family("room");
}
TEST_P(AccelDifferential, ThinTinyAndHugeTriangles) {
  run_family("thin");
}
TEST_P(AccelDifferential, SpheresQuadsAndTriangles) {
  run_family("mixed");
}
TEST_P(AccelDifferential, CoincidentSurfacesGoToTheLowerId) {
  run_family("coincident");
}
TEST_P(AccelDifferential, DegenerateAndNonFiniteTriangles) {
  run_family("degenerate");
}
TEST_P(AccelDifferential, ScenesFrom1em10To1e10InSizeAndFarFromTheOrigin) {
  run_family("scaled");
}
TEST_P(AccelDifferential, SceneWhoseExtentOverflowsFloat) { run_family("float_range"); }
TEST_P(AccelDifferential, TessellatedTorus) {
  run_family("torus");
}

TEST_P(AccelDifferential, MovingTriangleSoup) {
  run_family("moving_soup");
}
TEST_P(AccelDifferential, MovingSpheresQuadsAndTriangles) {
  run_family("moving_shapes");
}
TEST_P(AccelDifferential, StaticRoomWithMovingPrimitives) {
  run_family("static_and_moving");
}

// Rays with a NaN or infinite origin or direction, a zero direction, or an empty or NaN
// interval never reach a traversal loop (a NaN slab test passes every box: the wide BVH's
// stack used to overflow); every structure answers "no hit", as brute force does.
TEST_P(AccelDifferential, UntraceableRaysAreNeverHit) {
  const TestScene scene = mixed_shapes(21);
  auto accel = make_accelerator(GetParam());
  accel->build(scene.prims);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Ray> rays;
  const auto ray = [](Vec3 o, Vec3 d, float tmin = 0.0f, float tmax = kInfinity) {
    Ray r;
    r.o = o, r.d = d, r.tmin = tmin, r.tmax = tmax;
    return r;
  };
  for (const Vec3 o : {Vec3(nan, 0, 0), Vec3(0, kInfinity, 0), Vec3(0, 0, -kInfinity)})
    rays.push_back(ray(o, Vec3(0.3f, 0.2f, 0.9f)));
  for (const Vec3 d : {Vec3(nan, nan, nan), Vec3(0, nan, 1), Vec3(kInfinity, 0, 0), Vec3(0, 0, 0)})
    rays.push_back(ray(Vec3(0.1f, 0.2f, -9.0f), d));
  rays.push_back(ray(Vec3(0.1f, 0.2f, -9.0f), Vec3(0, 0, 1), 5.0f, 1.0f));
  rays.push_back(ray(Vec3(0.1f, 0.2f, -9.0f), Vec3(0, 0, 1), nan));
  rays.push_back(ray(Vec3(0.1f, 0.2f, -9.0f), Vec3(0, 0, 1), 0.0f, nan));
  for (const Ray& r : rays) {
    Hit hit;
    EXPECT_FALSE(accel->intersect(r, hit)) << describe(r);
    EXPECT_FALSE(hit.valid());
    EXPECT_FALSE(accel->occluded(r)) << describe(r);
  }
  // The same rays made traceable do hit: the scene is in their way.
  Hit hit;
  EXPECT_TRUE(accel->intersect(ray(Vec3(0.1f, 0.2f, -9.0f), Vec3(0, 0, 1)), hit));
}

TEST_P(AccelDifferential, EmptyAndAllInvalidSetsAreNeverHit) {
  PrimitiveSet empty, invalid;
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, std::nanf(""), 0}};
  m.indices = {0, 1, 2, 0, 1, 2};
  invalid.add_mesh(m, Transform(), 0);
  for (const PrimitiveSet* prims : {&empty, &invalid}) {
    auto accel = make_accelerator(GetParam());
    accel->build(*prims);
    const Ray ray{{0.2f, 0.2f, -1.0f}, {0, 0, 1}};
    Hit hit;
    EXPECT_FALSE(accel->intersect(ray, hit));
    EXPECT_FALSE(hit.valid());
    EXPECT_FALSE(accel->occluded(ray));
  }
}

TEST_P(AccelDifferential, RebuildReplacesThePreviousScene) {
  const TestScene a = random_soup(200, 1), b = random_soup(300, 2);
  auto accel = make_accelerator(GetParam());
  accel->build(a.prims);
  accel->build(b.prims);
  const auto rays = mixed_rays(b.prims, 2000, 3);
  const Case c{{"soup-b", {}}, rays, brute_hits(b.prims, rays)};
  // check() reads the scene from the case: compare against a copy-free view of b.
  size_t differ = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit h;
    accel->intersect(rays[i], h);
    if (h.valid() != c.reference[i].valid() || (h.valid() && !same_hit(h, c.reference[i])))
      ++differ;
  }
  EXPECT_EQ(differ, 0u);
}

TEST_P(AccelDifferential, StatsAreConsistent) {
  const TestScene s = random_soup(500, 5);
  auto accel = make_accelerator(GetParam());
  accel->build(s.prims);
  const AccelStats st = accel->stats();
  EXPECT_GE(st.nodes, st.leaves);
  EXPECT_GE(st.leaves, 1u);
  EXPECT_GE(st.prim_refs, 500u);
  EXPECT_GT(st.bytes, 0u);
  EXPECT_GE(st.build_ms, 0.0);
  EXPECT_EQ(accel->name().substr(0, GetParam().size()), GetParam());
}

INSTANTIATE_TEST_SUITE_P(Registry, AccelDifferential, ::testing::ValuesIn(structure_names()),
                         [](const auto& info) { return structure_test_name(info.param); });

/// The occlusion reference above is derived from closest hits; check that derivation on brute.
TEST(BruteForce, OccludedAgreesWithClosestHit) {
  const TestScene s = mixed_shapes(21);
  const auto rays = mixed_rays(s.prims, 3000, 22);
  auto brute = make_accelerator("brute");
  brute->build(s.prims);
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit h;
    const bool hit = brute->intersect(rays[i], h);
    EXPECT_EQ(brute->occluded(rays[i]), hit) << i;
    if (hit) {
      Ray r = rays[i];
      r.tmax = h.t * 0.999f;
      EXPECT_FALSE(brute->occluded(r)) << i;
      r.tmax = h.t * 1.001f;
      EXPECT_TRUE(brute->occluded(r)) << i;
    }
  }
}

}  // namespace
}  // namespace penumbra::test
