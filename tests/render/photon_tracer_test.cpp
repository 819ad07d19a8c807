// Photon tracing against closed forms: power conservation in a closed diffuse box, emission in
// proportion to power, caustic classification behind a mirror, refraction in importance mode,
// directional and environment photons on an open floor, and determinism across thread counts.
// Every bound is a multiple of the standard error estimated from the per-photon contributions.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "penumbra/core/parallel.h"
#include "penumbra/render/photon/photon_tracer.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

/// The sum over N photons of one quantity, from each photon's own contribution (zero for most):
/// the sum estimates the expected total and its standard error is sqrt(N var(x)).
struct Tally {
  double sum = 0, sum2 = 0;
  uint64_t n = 0;
  void add(double x) { sum += x, sum2 += x * x, ++n; }
  double standard_error() const {
    if (n < 2) return 0.0;
    const double var = (sum2 - sum * sum / double(n)) / double(n - 1);
    return std::sqrt(std::fmax(var, 0.0) * double(n));
  }
};

/// Passes when the tally's sum lies within k standard errors (plus float slack) of `expected`,
/// and the standard error is positive (so the bound means something).
testing::AssertionResult within(const Tally& t, double expected, double k = 4.0) {
  const double se = t.standard_error(), slack = 1e-5 * std::fabs(expected);
  if (!(se > 0.0)) return testing::AssertionFailure() << "no spread: sum " << t.sum;
  if (std::fabs(t.sum - expected) <= k * se + slack) return testing::AssertionSuccess();
  return testing::AssertionFailure()
         << "sum " << t.sum << ", expected " << expected << " +- " << k << " x " << se;
}

std::string scene(const std::string& materials, const std::string& shapes,
                  const std::string& lights = "") {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]}},
    "materials": {{{}}},
    {}
    "shapes": [{}]}})",
                     materials, lights.empty() ? "" : "\"lights\": [" + lights + "],", shapes);
}

std::string quad(const char* o, const char* e1, const char* e2, const char* material,
                 const std::string& extra = "") {
  return fmt::format(R"({{"type": "quad", "origin": {}, "edge1": {}, "edge2": {},
      "material": "{}"{}}})",
                     o, e1, e2, material, extra);
}

/// The cube [-1, 1]^3 of six quads facing inwards (edge1 x edge2 points inside), material "m".
std::string closed_box() {
  const char* faces[6][3] = {
      {"[-1, -1, -1]", "[2, 0, 0]", "[0, 2, 0]"}, {"[-1, -1, 1]", "[0, 2, 0]", "[2, 0, 0]"},
      {"[-1, -1, -1]", "[0, 0, 2]", "[2, 0, 0]"}, {"[-1, 1, -1]", "[2, 0, 0]", "[0, 0, 2]"},
      {"[-1, -1, -1]", "[0, 2, 0]", "[0, 0, 2]"}, {"[1, -1, -1]", "[0, 0, 2]", "[0, 2, 0]"}};
  std::string s;
  for (const auto& f : faces) s += quad(f[0], f[1], f[2], "m") + ",";
  return s;
}

// A closed box, diffuse albedo rho on every surface (the emitter's too), one one-sided quad light
// of radiance L and area A below the ceiling facing down: power Phi = pi A L. No photon escapes,
// each scattering keeps the fraction rho on average, so the power arriving at depth d is
// Phi rho^d exactly. With grey rho the roulette survives with q = rho and each survivor keeps
// Phi / N: the count at depth d is binomial(N, rho^d).
TEST(PhotonTracer, ClosedDiffuseBoxConservesPowerAtEveryDepth) {
  const float rho = 0.5f, l = 2.0f, area = 0.25f;
  const World world(test::scene_from_text(scene(
                        fmt::format(R"("m": {{"type": "diffuse", "albedo": {}}})", rho),
                        closed_box() + quad("[-0.25, 0.9, -0.25]", "[0.5, 0, 0]", "[0, 0, 0.5]",
                                            "m", fmt::format(R"(, "emission": {})", l)))),
                    "bvh");
  const double phi = kPi * area * l;
  const uint64_t n = 40000;
  for (const int max_depth : {-1, 1}) {
    SCOPED_TRACE(fmt::format("max_depth {}", max_depth));
    const PhotonTracer tracer(world, max_depth);
    ASSERT_TRUE(tracer.has_lights());
    Tally depth_power[5];
    uint64_t rays = 0;
    int deepest = -1;
    for (uint64_t i = 0; i < n; ++i) {
      double mine[5] = {0, 0, 0, 0, 0};
      rays += tracer.trace(i, 7, n, [&](const PhotonHit& h) {
        deepest = std::max(deepest, h.depth);
        if (h.depth < 5) mine[h.depth] += h.power.g;
        EXPECT_FALSE(h.caustic);  // no specular surface anywhere
        // Survivors of the roulette keep the emitted power Phi / N (Jensen 1996).
        EXPECT_NEAR(h.power.g, phi / double(n), 1e-4 * phi / double(n));
        // The emitter faces down: no direct photon lands on its own plane.
        if (h.depth == 0) {
          EXPECT_GT(std::fabs(h.si->p.y - 0.9f), 1e-3f);
        }
        return true;
      });
      for (int d = 0; d < 5; ++d) depth_power[d].add(mine[d]);
    }
    const int checked = max_depth < 0 ? 4 : 2;
    for (int d = 0; d < checked; ++d)
      EXPECT_TRUE(within(depth_power[d], phi * std::pow(rho, d))) << "depth " << d;
    if (max_depth >= 0) {
      EXPECT_EQ(deepest, max_depth);
      EXPECT_LE(rays, n * uint64_t(max_depth + 1));  // one ray per scattering event, no more
    } else {
      EXPECT_GT(deepest, 4);
    }
    // Every photon's first ray hits the box.
    EXPECT_GE(rays, n);
  }
}

// A point light of intensity I (power 4 pi I) inside a closed sphere at x = -5 and a coloured
// quad light of radiance L, area A (power pi A L) inside another at x = +5: every direct photon
// lands inside the sphere around its own light. "power" picks lights by the luminance of their
// power, so the share of photons is lum(Phi_i) / sum lum, and the direct power in each sphere is
// that light's power per channel; "uniform" picks each with 1/2 and still delivers each power.
TEST(PhotonTracer, LightsEmitInProportionToTheirPower) {
  const float intensity = 0.1f;
  const Rgb radiance(3.0f, 1.0f, 0.5f);
  const float area = 0.16f;
  const World world(
      test::scene_from_text(
          scene(R"("m": {"type": "diffuse", "albedo": 0.5})",
                R"({"type": "sphere", "center": [-5, 0, 0], "radius": 1, "material": "m"},
             {"type": "sphere", "center": [5, 0, 0], "radius": 1, "material": "m"},)" +
                    quad("[4.8, 0.5, -0.2]", "[0.4, 0, 0]", "[0, 0, 0.4]", "m",
                         R"(, "emission": [3, 1, 0.5])"),
                fmt::format(R"({{"type": "point", "position": [-5, 0, 0], "intensity": {}}})",
                            intensity))),
      "bvh");
  const Rgb phi_point = Rgb(intensity) * float(4.0 * kPi);
  const Rgb phi_area = radiance * float(kPi * area);
  const auto lum = [](Rgb c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  const uint64_t n = 40000;
  for (const char* strategy : {"power", "uniform"}) {
    SCOPED_TRACE(strategy);
    const PhotonTracer tracer(world, 0, strategy);
    const double p_point = std::string(strategy) == "uniform"
                               ? 0.5
                               : lum(phi_point) / (lum(phi_point) + lum(phi_area));
    Tally count_point, power[2][3];  // [point, area][channel]
    for (uint64_t i = 0; i < n; ++i) {
      double mine[2][3] = {{0, 0, 0}, {0, 0, 0}};
      int hits = 0;
      tracer.trace(i, 3, n, [&](const PhotonHit& h) {
        EXPECT_EQ(h.depth, 0);
        const int side = h.si->p.x < 0.0f ? 0 : 1;
        for (int c = 0; c < 3; ++c) mine[side][c] += h.power[c];
        ++hits;
        return true;
      });
      EXPECT_EQ(hits, 1);  // max_depth 0: one direct hit, inside a closed sphere
      count_point.add(mine[0][1] > 0.0 ? 1.0 : 0.0);
      for (int s = 0; s < 2; ++s)
        for (int c = 0; c < 3; ++c) power[s][c].add(mine[s][c]);
    }
    EXPECT_TRUE(within(count_point, p_point * double(n)));
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(within(power[0][c], phi_point[c])) << "point light, channel " << c;
      EXPECT_TRUE(within(power[1][c], phi_area[c])) << "area light, channel " << c;
    }
  }
}

/// A point light at height 1 below a 2 x 2 mirror of reflectance R at height 2 (or a diffuse
/// quad), above a diffuse 8 x 8 floor at height 0.
std::string mirror_scene(bool mirror) {
  return scene(
      R"("floor": {"type": "diffuse", "albedo": 0.5},
         "mirror": {"type": "mirror", "reflectance": 0.8},
         "matte": {"type": "diffuse", "albedo": 0.8})",
      quad("[-4, 0, -4]", "[0, 0, 8]", "[8, 0, 0]", "floor") + "," +
          quad("[-1, 2, -1]", "[2, 0, 0]", "[0, 0, 2]", mirror ? "mirror" : "matte"),
      R"({"type": "point", "position": [0, 1, 0], "intensity": 2})");
}

bool same_photon(const Photon& a, const Photon& b) {
  return a.p == b.p && a.wi.u == b.wi.u && a.wi.v == b.wi.v && a.power == b.power;
}

// The mirror subtends the solid angle of a square of side a at distance h, 4 asin(a^2 / (a^2 +
// 4 h^2)) = 4 asin(1/2) = 2 pi / 3, from the light; every photon it reflects continues from the
// light's image at height 3 through the mirror onto the floor within |x|, |z| <= 3. So the caustic
// power is R I 2 pi / 3, all at depth 1. kCaustic keeps exactly the hits trace() flags caustic,
// kAll keeps every hit, kIndirect every hit past the first; with a diffuse quad in place of the
// mirror there is no caustic at all (though light still bounces off it).
TEST(PhotonTracer, CausticMapKeepsOnlyLightFromSpecularBounces) {
  const float r = 0.8f, intensity = 2.0f;
  const uint64_t n = 30000, seed = 11;
  const World world(test::scene_from_text(mirror_scene(true)), "bvh");
  const PhotonTracer tracer(world, -1);
  const PhotonBatch caustic = tracer.trace_batch(n, seed, PhotonStore::kCaustic);
  const PhotonBatch all = tracer.trace_batch(n, seed, PhotonStore::kAll);
  const PhotonBatch indirect = tracer.trace_batch(n, seed, PhotonStore::kIndirect);
  EXPECT_EQ(caustic.emitted, n);

  // The same photons, hit by hit, from trace() itself.
  std::vector<Photon> every, flagged, past_first;
  Tally caustic_power;
  for (uint64_t i = 0; i < n; ++i) {
    double mine = 0;
    tracer.trace(i, seed, n, [&](const PhotonHit& h) {
      const Photon p{h.si->p, OctDirection::encode(h.si->wo), h.power};
      every.push_back(p);
      if (h.depth >= 1) past_first.push_back(p);
      if (h.caustic) {
        flagged.push_back(p);
        mine += h.power.g;
        EXPECT_EQ(h.depth, 1);
        EXPECT_NEAR(h.si->p.y, 0.0f, 1e-5f);
        EXPECT_LE(std::fabs(h.si->p.x), 3.0f + 1e-3f);
        EXPECT_LE(std::fabs(h.si->p.z), 3.0f + 1e-3f);
        EXPECT_GT(h.si->wo.y, 0.0f);  // it came down from the mirror
      }
      if (h.depth == 0) {
        EXPECT_FALSE(h.caustic);
      }
      return true;
    });
    caustic_power.add(mine);
  }
  EXPECT_TRUE(within(caustic_power, r * intensity * 2.0 * kPi / 3.0));
  ASSERT_EQ(caustic.photons.size(), flagged.size());
  for (size_t i = 0; i < flagged.size(); ++i)
    EXPECT_TRUE(same_photon(caustic.photons[i], flagged[i])) << "caustic photon " << i;
  ASSERT_EQ(all.photons.size(), every.size());
  for (size_t i = 0; i < every.size(); ++i)
    ASSERT_TRUE(same_photon(all.photons[i], every[i])) << "photon " << i;
  ASSERT_EQ(indirect.photons.size(), past_first.size());
  for (size_t i = 0; i < past_first.size(); ++i)
    ASSERT_TRUE(same_photon(indirect.photons[i], past_first[i])) << "indirect photon " << i;
  EXPECT_GT(all.photons.size(), indirect.photons.size());
  EXPECT_GT(indirect.photons.size(), caustic.photons.size());
  // A caustic path ends at its first non-specular hit: fewer rays than the full paths.
  EXPECT_LT(caustic.rays, all.rays);

  // No specular surface: no caustic, although photons bounce off the matte quad.
  const World matte(test::scene_from_text(mirror_scene(false)), "bvh");
  const PhotonTracer matte_tracer(matte, -1);
  EXPECT_TRUE(matte_tracer.trace_batch(n, seed, PhotonStore::kCaustic).photons.empty());
  EXPECT_FALSE(matte_tracer.trace_batch(n, seed, PhotonStore::kIndirect).photons.empty());
}

/// A directional light straight down (irradiance E) onto a smooth glass interface (or two, a
/// slab) above a 2 x 2 diffuse floor.
std::string glass_scene(bool slab) {
  std::string shapes = quad("[-1, 0, -1]", "[0, 0, 2]", "[2, 0, 0]", "floor") + "," +
                       quad("[-1, 1, -1]", "[0, 0, 2]", "[2, 0, 0]", "glass");  // faces up
  if (slab) {  // facing down (appended in two steps: "," + std::string trips GCC 12's -Wrestrict)
    shapes += ",";
    shapes += quad("[-1, 0.8, -1]", "[2, 0, 0]", "[0, 0, 2]", "glass");
  }
  return scene(R"("floor": {"type": "diffuse", "albedo": 0.5},
                  "glass": {"type": "dielectric", "ior": 1.5})",
               shapes, R"({"type": "directional", "direction": [0, -1, 0], "irradiance": 2})");
}

// At normal incidence a smooth interface of relative index 1.5 reflects F = (0.5 / 2.5)^2 = 0.04
// from either side. Importance is not scaled by 1/eta^2 (Veach 1997, section 5.2): a photon that
// refracts keeps its power, so the floor under one interface receives E A (1 - F) and the floor
// under a slab E A (1 - F)^2 at depth 2 (radiance scaling would give 1/2.25 of the first).
// Photons leave a disc of radius r (the scene's bounding sphere) with power E pi r^2 / N.
TEST(PhotonTracer, RefractionKeepsPhotonPowerInImportanceMode) {
  const double e = 2.0, area = 4.0, f = 0.04;
  const uint64_t n = 30000;
  for (const bool slab : {false, true}) {
    SCOPED_TRACE(slab ? "slab" : "single interface");
    const World world(test::scene_from_text(glass_scene(slab)), "bvh");
    const PhotonTracer tracer(world, -1);
    const Vec3 half = (world.bounds().hi - world.bounds().lo) * 0.5f;
    const double radius = length(half);
    const double photon_power = e * kPi * radius * radius / double(n);
    const int through = slab ? 2 : 1;  // the depth of the floor hit straight through the glass
    Tally floor;
    for (uint64_t i = 0; i < n; ++i) {
      double mine = 0;
      tracer.trace(i, 5, n, [&](const PhotonHit& h) {
        if (h.depth == through && h.si->p.y < 0.5f) {
          mine += h.power.g;
          EXPECT_TRUE(h.caustic);
          EXPECT_NEAR(h.power.g, photon_power, 1e-4 * photon_power);  // power kept per photon
        }
        return true;
      });
      floor.add(mine);
    }
    EXPECT_TRUE(within(floor, e * area * std::pow(1.0 - f, through)));
  }
}

// A directional light of irradiance E along d onto a horizontal floor of area A: the floor
// receives E A |cos theta| directly, where cos theta = d.y / |d|; nothing else is hit first.
TEST(PhotonTracer, DirectionalLightDeliversIrradianceTimesProjectedArea) {
  const World world(
      test::scene_from_text(scene(
          R"("m": {"type": "diffuse", "albedo": 0.5})",
          quad("[-2, 0, -2]", "[0, 0, 4]", "[4, 0, 0]", "m"),
          R"({"type": "directional", "direction": [0.3, -1, 0.2], "irradiance": [1, 2, 3]})")),
      "bvh");
  const PhotonTracer tracer(world, 0);
  const double cos_theta = 1.0 / std::sqrt(0.09 + 1.0 + 0.04), area = 16.0;
  const uint64_t n = 20000;
  Tally power[3];
  for (uint64_t i = 0; i < n; ++i) {
    double mine[3] = {0, 0, 0};
    tracer.trace(i, 9, n, [&](const PhotonHit& h) {
      EXPECT_GT(h.si->wo.y, 0.0f);  // from above
      for (int c = 0; c < 3; ++c) mine[c] += h.power[c];
      return true;
    });
    for (int c = 0; c < 3; ++c) power[c].add(mine[c]);
  }
  for (int c = 0; c < 3; ++c)
    EXPECT_TRUE(within(power[c], (c + 1.0) * area * cos_theta)) << "channel " << c;
}

// A uniform environment of radiance L around a lone floor of area A: each side receives the
// irradiance pi L, so 2 pi L A arrives in all (the integral of L A |cos| over the sphere); the
// photons enter through the disc that covers the scene's bounding sphere.
TEST(PhotonTracer, EnvironmentLightIrradiatesBothSidesOfAFloor) {
  const World world(
      test::scene_from_text(scene(R"("m": {"type": "diffuse", "albedo": 0.5})",
                                  quad("[-1, 0, -1]", "[0, 0, 2]", "[2, 0, 0]", "m"),
                                  R"({"type": "environment", "radiance": [0.5, 1, 2]})")),
      "bvh");
  const PhotonTracer tracer(world, 0);
  const double l[3] = {0.5, 1.0, 2.0}, area = 4.0;
  const uint64_t n = 20000;
  Tally power[3], below;
  for (uint64_t i = 0; i < n; ++i) {
    double mine[3] = {0, 0, 0}, under = 0;
    tracer.trace(i, 13, n, [&](const PhotonHit& h) {
      for (int c = 0; c < 3; ++c) mine[c] += h.power[c];
      if (h.si->wo.y < 0.0f) under += h.power.g;
      return true;
    });
    for (int c = 0; c < 3; ++c) power[c].add(mine[c]);
    below.add(under);
  }
  for (int c = 0; c < 3; ++c)
    EXPECT_TRUE(within(power[c], 2.0 * kPi * l[c] * area)) << "channel " << c;
  EXPECT_TRUE(within(below, kPi * l[1] * area));  // the lower side, pi L A
}

// Light leaves an emitter from its surface: a convex one-sided emitter (a sphere, a tilted quad)
// never receives its own direct photons, also where it passes near the world's origin (points
// there are small, their rounding error is not). Without moving the origin off the surface about
// half the photons would hit the emitter itself at t ~ 0.
TEST(PhotonTracer, PhotonsDoNotHitTheirOwnEmitter) {
  for (const char* emitter :
       {R"({"type": "sphere", "center": [0.3, 0.1, -0.2], "radius": 0.37, "material": "m",
            "emission": 1})",
        R"({"type": "quad", "origin": [-0.3, 0.3, 0.1], "edge1": [0.61, 0.13, 0.07],
            "edge2": [0.05, -0.2, 0.53], "material": "m", "emission": 1})"}) {
    SCOPED_TRACE(emitter);
    const std::string enclosure =
        R"({"type": "sphere", "center": [0, 0, 0], "radius": 5, "material": "m"})";
    const World world(test::scene_from_text(scene(R"("m": {"type": "diffuse", "albedo": 0.5})",
                                                  std::string(emitter) + "," + enclosure)),
                      "bvh");
    const PhotonTracer tracer(world, 0);
    const uint64_t n = 50000;
    uint64_t own = 0, hits = 0;
    for (uint64_t i = 0; i < n; ++i)
      tracer.trace(i, 17, n, [&](const PhotonHit& h) {
        ++hits;
        own += h.si->prim == 0;
        return true;
      });
    EXPECT_EQ(hits, n);  // every photon lands on the enclosure
    EXPECT_EQ(own, 0u);
  }
}

/// A small room with glass, metal and diffuse surfaces and a quad light.
std::string room_scene() {
  return scene(
      R"("white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
         "red": {"type": "diffuse", "albedo": [0.7, 0.2, 0.1]},
         "metal": {"type": "conductor", "reflectance": [0.9, 0.8, 0.5], "roughness": 0.35},
         "glass": {"type": "dielectric", "ior": 1.5})",
      quad("[-3, 0, -3]", "[0, 0, 6]", "[6, 0, 0]", "white") + "," +
          quad("[-3, 0, 2]", "[6, 0, 0]", "[0, 4, 0]", "red") + "," +
          quad("[-0.6, 2.6, -0.6]", "[1.2, 0, 0]", "[0, 0, 1.2]", "white",
               R"(, "emission": [6, 6, 6])") +
          R"(, {"type": "sphere", "center": [-1.1, 0.6, 0.3], "radius": 0.6, "material": "metal"},
          {"type": "sphere", "center": [0.2, 0.5, -0.6], "radius": 0.5, "material": "glass"},
          {"type": "sphere", "center": [1.2, 0.5, 0.5], "radius": 0.5, "material": "white"})",
      R"({"type": "point", "position": [0, 2, -1], "intensity": 3})");
}

// The batch does not depend on the thread count: chunks are fixed and each photon's numbers
// depend only on (index, seed). n is not a multiple of the chunk size.
TEST(PhotonTracer, BatchIsIdenticalAtOneAndTwoThreads) {
  const World world(test::scene_from_text(room_scene()), "bvh");
  const PhotonTracer tracer(world, -1);
  const uint64_t n = 10000;
  for (const PhotonStore what : {PhotonStore::kAll, PhotonStore::kCaustic}) {
    PhotonBatch one, two;
    {
      const ThreadLimit limit(1);
      one = tracer.trace_batch(n, 21, what);
    }
    {
      const ThreadLimit limit(2);
      two = tracer.trace_batch(n, 21, what);
    }
    ASSERT_FALSE(one.photons.empty());
    ASSERT_EQ(one.photons.size(), two.photons.size());
    EXPECT_EQ(one.rays, two.rays);
    EXPECT_EQ(one.emitted, n);
    EXPECT_EQ(0, std::memcmp(one.photons.data(), two.photons.data(),
                             one.photons.size() * sizeof(Photon)));
  }
  // Another seed gives other photons.
  const PhotonBatch a = tracer.trace_batch(n, 21, PhotonStore::kAll);
  const PhotonBatch b = tracer.trace_batch(n, 22, PhotonStore::kAll);
  EXPECT_FALSE(a.photons.size() == b.photons.size() &&
               std::memcmp(a.photons.data(), b.photons.data(), a.photons.size() * sizeof(Photon)) ==
                   0);
}

// Cancelled before the start: nothing traced, emitted still n; progress reaches 1 otherwise.
TEST(PhotonTracer, CancelStopsAndProgressReachesOne) {
  const World world(test::scene_from_text(room_scene()), "bvh");
  const PhotonTracer tracer(world, -1);
  const std::atomic<bool> cancel{true};
  const PhotonBatch none = tracer.trace_batch(20000, 1, PhotonStore::kAll, &cancel);
  EXPECT_TRUE(none.photons.empty());
  EXPECT_EQ(none.rays, 0u);
  EXPECT_EQ(none.emitted, 20000u);
  std::atomic<int> calls{0};
  std::atomic<double> last{0.0};
  const PhotonBatch done = tracer.trace_batch(20000, 1, PhotonStore::kAll, nullptr, [&](double f) {
    ++calls;
    double seen = last.load();
    while (f > seen && !last.compare_exchange_weak(seen, f)) {
    }
  });
  EXPECT_EQ(calls.load(), 5);  // ceil(20000 / 4096) chunks
  EXPECT_DOUBLE_EQ(last.load(), 1.0);
  EXPECT_FALSE(done.photons.empty());
}

// A world without lights traces nothing.
TEST(PhotonTracer, NoLightsNoPhotons) {
  const World world(
      test::scene_from_text(scene(R"("m": {"type": "diffuse", "albedo": 0.5})",
                                  quad("[-1, 0, -1]", "[0, 0, 2]", "[2, 0, 0]", "m"))),
      "bvh");
  const PhotonTracer tracer(world, -1);
  EXPECT_FALSE(tracer.has_lights());
  const PhotonBatch b = tracer.trace_batch(1000, 1, PhotonStore::kAll);
  EXPECT_TRUE(b.photons.empty());
  EXPECT_EQ(b.rays, 0u);
}

}  // namespace
}  // namespace penumbra
