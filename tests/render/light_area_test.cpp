// Area lights: the directions sample_li draws against pdf_li (chi-square), pdf_li against each
// sample's pdf, irradiance estimates against closed forms, and emitted rays (sample_le, pdf_le).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "chi_square.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/light/area_light.h"
#include "penumbra/render/light/light_sampler.h"
#include "penumbra/render/sampling.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

/// A scene of emissive shapes (JSON array text) and its world: the world keeps the description.
struct TestWorld {
  explicit TestWorld(const std::string& shapes)
      : desc(test::scene_from_text(
            R"({"camera": {"type": "pinhole", "position": [0, 0, -9], "look_at": [0, 0, 0]},
                "materials": {"b": {"type": "diffuse", "albedo": 0}}, "shapes": [)" +
            shapes + "]}")),
        world(std::make_unique<World>(desc, "bvh")) {}
  const Light& light(size_t i = 0) const { return world->area_light(i); }
  SceneDesc desc;
  std::unique_ptr<World> world;
};

using test::chi_square;

/// Solid-angle density of directions from `p` that a strategy claims (zero where nothing is hit).
using DirectionPdf = std::function<float(Vec3 w, const SurfaceInteraction& si)>;

/// Bins the directions of `n` samples by (1 - cos theta, phi) about `axis` on [cos_min, 1] (plus a
/// bin for "no sample"), compares them with N times the integral of `pdf` over each cell (adaptive
/// quadrature, a ray per point), and checks every sample's pdf against `pdf` for its direction.
/// 1 - cos theta is computed as |w - axis|^2 / 2 in double, so narrow cones keep their digits.
void expect_directions_follow_pdf(const World& world, Vec3 p, Vec3 axis, float cos_min,
                                  const std::function<LightSample(Vec2)>& sample,
                                  const DirectionPdf& pdf, uint64_t seed, int n = 200000) {
  constexpr int kCos = 16, kPhi = 16, kSub = 16, kFine = 12;
  Vec3 t, b;
  orthonormal_basis(axis, t, b);
  RayCounter counter;
  const auto density = [&](Vec3 w) {
    SurfaceInteraction si;
    return world.intersect({p, w}, si, counter) ? pdf(w, si) : 0.0f;
  };
  const auto direction = [&](double s, double phi) {  // s = 1 - cos theta
    const double sin_t = std::sqrt(std::fmax(0.0, s * (2.0 - s)));
    return normalize(t * float(sin_t * std::cos(phi)) + b * float(sin_t * std::sin(phi)) +
                     axis * float(1.0 - s));
  };
  const auto one_minus_cos = [&](Vec3 w) {
    const double l = std::sqrt(double(w.x) * w.x + double(w.y) * w.y + double(w.z) * w.z);
    const double dx = w.x / l - axis.x, dy = w.y / l - axis.y, dz = w.z / l - axis.z;
    return 0.5 * (dx * dx + dy * dy + dz * dz);
  };
  // Expected counts: N times the integral of the density over each cell. The density is known on
  // a lattice of kSub x kSub sub-cells per cell; a sub-cell is integrated by the trapezoid rule
  // where its corners agree within 10%, else by kFine x kFine midpoints, and so are those within
  // two sub-cells of such a one: a thin corner of a light between lattice points is not lost.
  const double ds = (1.0 - double(cos_min)) / kCos, dphi = 2.0 * kPi / kPhi;
  const int ns = kCos * kSub, nphi = kPhi * kSub;  // sub-cells; phi wraps around
  const double hs = ds / kSub, hphi = dphi / kSub;
  std::vector<float> lattice(size_t(ns + 1) * nphi);
  for (int a = 0; a <= ns; ++a)
    for (int c = 0; c < nphi; ++c) lattice[a * nphi + c] = density(direction(a * hs, c * hphi));
  const auto corner = [&](int a, int c) { return double(lattice[a * nphi + (c + nphi) % nphi]); };
  std::vector<uint8_t> rough(size_t(ns) * nphi);
  for (int a = 0; a < ns; ++a)
    for (int c = 0; c < nphi; ++c) {
      const double f[4] = {corner(a, c), corner(a, c + 1), corner(a + 1, c), corner(a + 1, c + 1)};
      rough[a * nphi + c] = *std::max_element(f, f + 4) > 1.1 * *std::min_element(f, f + 4);
    }
  std::vector<double> expected(kCos * kPhi + 1, 0.0), observed(kCos * kPhi + 1, 0.0);
  double total = 0;
  for (int a = 0; a < ns; ++a)
    for (int c = 0; c < nphi; ++c) {
      bool refine = false;
      for (int x = std::max(a - 2, 0); x <= std::min(a + 2, ns - 1); ++x)
        for (int y = c - 2; y <= c + 2; ++y) refine |= rough[x * nphi + (y + nphi) % nphi] != 0;
      double integral = 0;
      if (!refine) {
        integral =
            0.25 * (corner(a, c) + corner(a, c + 1) + corner(a + 1, c) + corner(a + 1, c + 1));
      } else {
        for (int x = 0; x < kFine; ++x)
          for (int y = 0; y < kFine; ++y)
            integral +=
                density(direction((a + (x + 0.5) / kFine) * hs, (c + (y + 0.5) / kFine) * hphi));
        integral /= kFine * kFine;
      }
      expected[(a / kSub) * kPhi + c / kSub] += n * integral * hs * hphi;
      total += n * integral * hs * hphi;
    }
  expected.back() = n - total;  // samples that found nothing (the light seen from behind)
  // Observed counts, and each sample's pdf against the density of its direction.
  Pcg32 rng(seed);
  int pdf_mismatches = 0;
  for (int k = 0; k < n; ++k) {
    const LightSample ls = sample({rng.next_float(), rng.next_float()});
    if (!(ls.pdf > 0.0f) || ls.li.is_black()) {
      observed.back() += 1;
      continue;
    }
    const double s = one_minus_cos(ls.wi);
    double phi = std::atan2(double(dot(ls.wi, b)), double(dot(ls.wi, t)));
    if (phi < 0) phi += 2.0 * kPi;
    ASSERT_LE(s, ds * kCos) << "a sample outside the binned cone";
    const int i = std::min(int(s / ds), kCos - 1), j = std::min(int(phi / dphi), kPhi - 1);
    observed[i * kPhi + j] += 1;
    if (std::fabs(density(ls.wi) - ls.pdf) > 1e-3f * ls.pdf) ++pdf_mismatches;
  }
  EXPECT_TRUE(chi_square(observed, expected));
  // A direction through an edge may miss by rounding: a handful, not a fraction.
  EXPECT_LE(pdf_mismatches, n / 5000) << "samples whose pdf differs from pdf_li";
}

/// expect_directions_follow_pdf for one light.
void expect_light_follows_pdf(const TestWorld& tw, const Light& light, Vec3 p, Vec3 axis,
                              float cos_min, uint64_t seed) {
  expect_directions_follow_pdf(
      *tw.world, p, normalize(axis), cos_min, [&](Vec2 u) { return light.sample_li(p, u); },
      [&](Vec3 w, const SurfaceInteraction& si) {
        return si.area_light == &light ? light.pdf_li(p, w, si.light_point()) : 0.0f;
      },
      seed);
}

/// A one-sided box of 12 outward-facing triangles, 1 x 1.4 x 1.8, of radiance 2.
const char* kCube = R"({"type": "mesh", "material": "b", "emission": 2,
    "positions": [[-1,-1,-1],[1,-1,-1],[1,1,-1],[-1,1,-1],[-1,-1,1],[1,-1,1],[1,1,1],[-1,1,1]],
    "indices": [[0,2,1],[0,3,2],[4,5,6],[4,6,7],[0,1,5],[0,5,4],[3,7,6],[3,6,2],[0,4,7],[0,7,3],
                [1,2,6],[1,6,5]], "transform": [{"scale": [0.5, 0.7, 0.9]}]})";

TEST(AreaLight, TriangleDirectionsFollowPdf) {
  const TestWorld tw(R"({"type": "mesh", "material": "b", "emission": 1,
      "positions": [[0, 0, 0], [1, 0, 0], [0.2, 1.5, 0]], "indices": [[0, 1, 2]]})");
  expect_light_follows_pdf(tw, tw.light(), {0.3f, 0.2f, 0.7f}, {0.1f, 0.3f, -0.7f}, 0.5f, 1);
}

TEST(AreaLight, SphereFromOutsideDirectionsFollowPdf) {
  const TestWorld tw(R"({"type": "sphere", "center": [0, 0, 2], "radius": 1, "material": "b",
      "emission": 1})");
  expect_light_follows_pdf(tw, tw.light(), {0, 0, 0}, {0, 0, 1}, 0.85f, 2);
}

TEST(AreaLight, SphereFromInsideDirectionsFollowPdf) {
  const TestWorld tw(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "b",
      "emission": 1, "two_sided": true})");
  expect_light_follows_pdf(tw, tw.light(), {0.2f, 0.5f, -0.1f}, {0, 0, 1}, -1.0f, 303);
}

TEST(AreaLight, RectangleDirectionsFollowPdf) {
  // A tilted rectangle whose front faces the receiver, seen at about 1 sr: spherical sampling.
  const TestWorld tw(R"({"type": "quad", "origin": [-1, -0.5, 0.6], "edge1": [0, 1.5, 0.5],
      "edge2": [2, 0, 0], "material": "b", "emission": 1})");
  expect_light_follows_pdf(tw, tw.light(), {0.5f, 0.1f, 0}, {0, -1, 3}, 0.3f, 4);
}

TEST(AreaLight, SkewedAndFarQuadsDirectionsFollowPdf) {
  // A parallelogram (area sampling) and a rectangle of tiny solid angle (area sampling).
  const TestWorld tw(R"({"type": "quad", "origin": [-1, -0.5, 1], "edge1": [0.7, 1, 0],
      "edge2": [2, 0, 0], "material": "b", "emission": 1},
      {"type": "quad", "origin": [0, 0, -100], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
       "material": "b", "emission": 1})");
  expect_light_follows_pdf(tw, tw.light(0), {0, 0, 0}, {0, 0, 1}, 0.4f, 5);
  expect_light_follows_pdf(tw, tw.light(1), {0.2f, 0.3f, 0}, {0.3f, 0.2f, -100}, 0.99995f, 6);
}

TEST(AreaLight, MeshDirectionsFollowPdf) {
  // A one-sided closed mesh: the faces turned away are sampled too, and yield nothing.
  const TestWorld tw(kCube);
  expect_light_follows_pdf(tw, tw.light(), {1.5f, 1.2f, -2.0f}, {-1.5f, -1.2f, 2.0f}, 0.6f, 7);
}

TEST(AreaLight, TrianglePairsThatFormAParallelogramAreOneUnit) {
  // The cube's faces are fans of two triangles: six parallelograms. The mesh below has, in order,
  // a parallelogram pair (a sheared quad), a kite (two triangles sharing an edge whose other
  // vertices are not mirror images: apart), a pair wound in opposite directions (front sides
  // facing away from each other: apart) and a lone triangle.
  const TestWorld cube(kCube);
  EXPECT_EQ(static_cast<const AreaLight&>(cube.light()).unit_count(), 6u);
  const TestWorld tw(R"({"type": "mesh", "material": "b", "emission": 1,
      "positions": [[0, 0, 0], [2, 0, 0], [2.5, 1, 0], [0.5, 1, 0],
                    [3, 0, 0], [4, 0, 0], [4, 1, 0], [3.2, 3, 0],
                    [5, 0, 0], [6, 0, 0], [6, 1, 0], [5, 1, 0],
                    [7, 0, 0], [8, 0, 0], [7, 1, 0]],
      "indices": [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [8, 9, 10], [8, 11, 10],
                  [12, 13, 14]]})");
  const auto& light = static_cast<const AreaLight&>(tw.light());
  EXPECT_EQ(light.unit_count(), 6u);
  // Every primitive keeps its share of the area, pairs included, and the shares sum to 1.
  const PrimitiveSet& prims = tw.world->primitives();
  double sum = 0;
  for (uint32_t id = 0; id < prims.size(); ++id) {
    const double share = length(tw.world->area_normal(id)) / light.area();
    EXPECT_NEAR(light.prim_pmf(id), share, 1e-6) << "primitive " << id;
    sum += light.prim_pmf(id);
  }
  EXPECT_NEAR(sum, 1.0, 1e-6);
  // Seen from the front (+z; the wound-back triangle gives nothing from there), the directions
  // follow pdf_li over all of them.
  expect_light_follows_pdf(tw, light, {4.0f, 0.5f, 1.5f}, {0, 0, -1}, 0.15f, 21);
}

TEST(AreaLight, TwoSidedFromBehindDirectionsFollowPdf) {
  // Seen from the side the normals point away from: rectangle (spherical) and triangle (area).
  const TestWorld tw(R"({"type": "quad", "origin": [-1, -1, 1], "edge1": [2, 0, 0],
      "edge2": [0, 2, 0], "material": "b", "emission": 1, "two_sided": true},
      {"type": "mesh", "material": "b", "emission": 1, "two_sided": true,
       "positions": [[0, 0, -1], [1, 0, -1], [0, 1, -1]], "indices": [[0, 2, 1]]})");
  expect_light_follows_pdf(tw, tw.light(0), {0.3f, 0.2f, 0.5f}, {0, 0, 1}, 0.2f, 8);
  expect_light_follows_pdf(tw, tw.light(1), {0.2f, 0.2f, -0.2f}, {0, 0, -1}, 0.4f, 9);
}

TEST(AreaLight, OneSidedFromBehindGivesNothing) {
  const TestWorld tw(R"({"type": "quad", "origin": [-1, -1, 1], "edge1": [2, 0, 0],
      "edge2": [0, 2, 0], "material": "b", "emission": 1})");
  const Light& light = tw.light();
  const Vec3 p{0, 0, 0};
  Pcg32 rng(10);
  for (int k = 0; k < 1000; ++k)
    EXPECT_EQ(light.sample_li(p, {rng.next_float(), rng.next_float()}).pdf, 0.0f);
  EXPECT_EQ(light.pdf_li(p, {0, 0, -1}, {{0, 0, 1}, {0, 0, 1}, 0}), 0.0f);
}

TEST(AreaLight, MixOfLightsThroughTheSamplerFollowsPdf) {
  // What a path tracer does: pick a light by power, then sample it; pdf = pmf * pdf_li.
  const TestWorld tw(std::string(kCube) + R"(, {"type": "sphere", "center": [2, 0, 0.5],
      "radius": 0.6, "material": "b", "emission": 3},
      {"type": "quad", "origin": [-2.5, -1, 0], "edge1": [0, 2, 0], "edge2": [0, 0, 1],
       "material": "b", "emission": [1, 2, 3], "two_sided": true})");
  const LightSampler sampler(tw.world->lights(), "power");
  const Vec3 p{0.2f, 0.1f, -3.0f};
  expect_directions_follow_pdf(
      *tw.world, p, {0, 0, 1}, 0.6f,
      [&](Vec2 u) {
        float u0;
        const SampledLight sl = sampler.sample(u.x, &u0);
        LightSample ls = sl.light->sample_li(p, {u0, u.y});
        ls.pdf *= sl.pmf;
        return ls;
      },
      [&](Vec3 w, const SurfaceInteraction& si) {
        return si.area_light
                   ? sampler.pmf(si.area_light) * si.area_light->pdf_li(p, w, si.light_point())
                   : 0.0f;
      },
      11);
}

/// Mean and standard deviation of the mean of the irradiance estimates L cos / pdf at p, normal n.
void estimate_irradiance(const Light& light, Vec3 p, Vec3 n, uint64_t seed, double& mean,
                         double& sigma) {
  Pcg32 rng(seed);
  const int count = 200000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < count; ++k) {
    const LightSample ls = light.sample_li(p, {rng.next_float(), rng.next_float()});
    const double e = ls.pdf > 0.0f ? ls.li.g * std::fmax(0.0f, dot(ls.wi, n)) / ls.pdf : 0.0;
    sum += e, sum2 += e * e;
  }
  mean = sum / count;
  sigma = std::sqrt(std::fmax(0.0, sum2 / count - mean * mean) / count);
}

/// Irradiance at p (unit normal n) from a polygon of radiance L wholly above p's horizon: Lambert's
/// formula E = L/2 |sum_i theta_i (n . u_i)|, u_i the unit normal of the plane through p and edge
/// i.
double polygon_irradiance(Vec3 p, Vec3 n, const std::vector<Vec3>& v, double l) {
  double sum = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec3 a = normalize(v[i] - p), b = normalize(v[(i + 1) % v.size()] - p);
    const double theta = std::acos(std::clamp(double(dot(a, b)), -1.0, 1.0));
    sum += theta * dot(normalize(cross(a, b)), n);
  }
  return 0.5 * l * std::fabs(sum);
}

TEST(AreaLight, IrradianceMatchesClosedForms) {
  const TestWorld tw(R"({"type": "sphere", "center": [0, 0, 3], "radius": 1.2, "material": "b",
      "emission": 2},
      {"type": "quad", "origin": [-1, -0.5, 0.5], "edge1": [0, 1.5, 0], "edge2": [2, 0, 0],
       "material": "b", "emission": 2},
      {"type": "mesh", "material": "b", "emission": 2,
       "positions": [[0, 0, 1], [1, 0, 1.5], [0.2, 1.5, 1]], "indices": [[0, 2, 1]]},
      {"type": "mesh", "material": "b", "emission": 2,
       "positions": [[-0.5, -0.4, 0.8], [0.9, -0.2, 1.1], [1.3, 1.0, 1.1], [-0.1, 0.8, 0.8]],
       "indices": [[0, 2, 1], [0, 3, 2]]})");
  double mean, sigma;
  // A sphere of radius r at distance d, facing it: E = pi L (r / d)^2.
  estimate_irradiance(tw.light(0), {0, 0, 0}, {0, 0, 1}, 12, mean, sigma);
  EXPECT_NEAR(mean, kPi * 2.0 * (1.2 * 1.2) / 9.0, 4.0 * sigma);
  // A rectangle close by (spherical sampling) and a triangle (area sampling), tilted receivers.
  const Vec3 n = normalize(Vec3{0.2f, 0.1f, 1.0f});
  estimate_irradiance(tw.light(1), {0.3f, 0.2f, 0}, n, 13, mean, sigma);
  EXPECT_NEAR(
      mean,
      polygon_irradiance({0.3f, 0.2f, 0}, n,
                         {{-1, -0.5f, 0.5f}, {1, -0.5f, 0.5f}, {1, 1, 0.5f}, {-1, 1, 0.5f}}, 2.0),
      4.0 * sigma);
  estimate_irradiance(tw.light(2), {0.2f, 0.3f, 0}, n, 14, mean, sigma);
  EXPECT_NEAR(
      mean, polygon_irradiance({0.2f, 0.3f, 0}, n, {{0, 0, 1}, {1, 0, 1.5f}, {0.2f, 1.5f, 1}}, 2.0),
      4.0 * sigma);
  // A tilted, sheared quad as two triangles, sampled as one parallelogram unit, against the
  // closed form of its outline (wound so that its front faces the receiver).
  ASSERT_EQ(static_cast<const AreaLight&>(tw.light(3)).unit_count(), 1u);
  estimate_irradiance(tw.light(3), {0.1f, 0.2f, 0}, n, 15, mean, sigma);
  EXPECT_NEAR(
      mean,
      polygon_irradiance(
          {0.1f, 0.2f, 0}, n,
          {{-0.5f, -0.4f, 0.8f}, {-0.1f, 0.8f, 0.8f}, {1.3f, 1.0f, 1.1f}, {0.9f, -0.2f, 1.1f}},
          2.0),
      4.0 * sigma);
}

TEST(AreaLight, ReceiverOnASphereSeesItsFarSide) {
  // A point of the sphere itself (rounded to either side of the surface, far from the origin):
  // sampled by area, every sample lies on the far side, and the irradiance of the inside of a
  // two-sided sphere of radiance L is pi L.
  const TestWorld tw(R"({"type": "sphere", "center": [10, -3, 2], "radius": 1.5, "material": "b",
      "emission": 2, "two_sided": true})");
  Pcg32 rng(19);
  const int n = 100000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const Vec3 w = sample_uniform_sphere({rng.next_float(), rng.next_float()});
    const Vec3 p = Vec3{10, -3, 2} + w * 1.5f;
    const LightSample ls = tw.light().sample_li(p, {rng.next_float(), rng.next_float()});
    if (!(ls.pdf > 0.0f)) continue;
    ASSERT_GT(ls.distance, 1e-3f) << "sampled the receiver itself";
    ASSERT_NEAR(length(p + ls.wi * ls.distance - Vec3{10, -3, 2}), 1.5f, 1e-3f);
    const double e = ls.li.g * std::fmax(0.0f, -dot(ls.wi, w)) / ls.pdf;
    sum += e, sum2 += e * e;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, kPi * 2.0, 4.0 * std::sqrt((sum2 / n - mean * mean) / n));
}

TEST(AreaLight, RectangleIsSampledUniformlyInSolidAngle) {
  const TestWorld tw(R"({"type": "quad", "origin": [-1, -0.5, 0.5], "edge1": [0, 1.5, 0],
      "edge2": [2, 0, 0], "material": "b", "emission": 1})");
  // The solid angle of the two triangles (Van Oosterom, Strackee 1983), in double.
  const auto tri = [](Vec3 a, Vec3 b, Vec3 c) {
    const double la = length(a), lb = length(b), lc = length(c);
    return 2.0 * std::atan2(std::fabs(double(dot(a, cross(b, c)))),
                            la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la);
  };
  const Vec3 p{0.3f, 0.2f, 0}, v0 = Vec3{-1, -0.5f, 0.5f} - p, v1 = Vec3{1, -0.5f, 0.5f} - p,
                               v2 = Vec3{1, 1, 0.5f} - p, v3 = Vec3{-1, 1, 0.5f} - p;
  const double omega = tri(v0, v1, v2) + tri(v0, v2, v3);
  Pcg32 rng(15);
  for (int k = 0; k < 1000; ++k) {
    const LightSample ls = tw.light().sample_li(p, {rng.next_float(), rng.next_float()});
    ASSERT_NEAR(ls.pdf, 1.0 / omega, 1e-5 / omega);
  }
}

TEST(AreaLight, EmittedRaysAreUniformByAreaAndCosineByDirection) {
  // Two-sided quad: bins of (u, v) on the quad, and of (side, cos^2 theta, phi): both uniform.
  const TestWorld tw(R"({"type": "quad", "origin": [0, 0, 0], "edge1": [2, 0, 0],
      "edge2": [0, 1, 0], "material": "b", "emission": 1, "two_sided": true})");
  const Light& light = tw.light();
  constexpr int kN = 8, n = 200000;
  std::vector<double> pos(kN * kN, 0.0), dir(2 * kN * kN, 0.0);
  Pcg32 rng(16);
  for (int k = 0; k < n; ++k) {
    const LightLeSample s = light.sample_le({rng.next_float(), rng.next_float()},
                                            {rng.next_float(), rng.next_float()}, 0.0f);
    const int pu = std::min(int(s.ray.o.x / 2.0f * kN), kN - 1),
              pv = std::min(int(s.ray.o.y * kN), kN - 1);
    pos[pu * kN + pv] += 1;
    const float c = s.ray.d.z;
    double phi = std::atan2(s.ray.d.y, s.ray.d.x) + kPi;
    dir[(c > 0 ? 0 : kN * kN) + std::min(int(c * c * kN), kN - 1) * kN +
        std::min(int(phi / (2 * kPi) * kN), kN - 1)] += 1;
    // pdf_le agrees with the sample's densities.
    float pdf_pos, pdf_dir;
    light.pdf_le(s.ray, s.n, pdf_pos, pdf_dir);
    ASSERT_NEAR(pdf_pos, s.pdf_pos, 1e-6f * s.pdf_pos);
    ASSERT_NEAR(pdf_dir, s.pdf_dir, 1e-4f * s.pdf_dir);
    ASSERT_NEAR(s.pdf_dir, std::fabs(c) / (2.0 * kPi), 1e-4);
  }
  EXPECT_TRUE(chi_square(pos, std::vector<double>(kN * kN, double(n) / (kN * kN))));
  EXPECT_TRUE(chi_square(dir, std::vector<double>(2 * kN * kN, double(n) / (2 * kN * kN))));
}

TEST(AreaLight, EmittedPowerMatchesPower) {
  // E[beta] = power, and an independent estimate: uniform points and directions, weighted by l().
  const TestWorld tw(std::string(kCube) + R"(, {"type": "sphere", "center": [3, 0, 0],
      "radius": 0.5, "material": "b", "emission": [1, 2, 3], "two_sided": true})");
  for (size_t i = 0; i < 2; ++i) {
    const auto& light = static_cast<const AreaLight&>(tw.light(i));
    Pcg32 rng(17 + i);
    const int n = 200000;
    double beta = 0, sum = 0, sum2 = 0;
    for (int k = 0; k < n; ++k) {
      const LightLeSample s = light.sample_le({rng.next_float(), rng.next_float()},
                                              {rng.next_float(), rng.next_float()}, 0.0f);
      beta += s.beta().g;
      const Vec3 w = sample_uniform_sphere({rng.next_float(), rng.next_float()});
      // s.n is the front normal for a one-sided light (two-sided ones emit either way).
      const double e =
          light.l({s.ray.o, s.n, 0}, w).g * std::fabs(dot(s.n, w)) * light.area() * 4.0 * kPi;
      sum += e, sum2 += e * e;
    }
    const double power = light.power().g, mean = sum / n;
    EXPECT_NEAR(beta / n, power, 1e-4 * power);  // beta is constant: L pi A (2 L pi A two-sided)
    EXPECT_NEAR(mean, power, 4.0 * std::sqrt((sum2 / n - mean * mean) / n));
  }
}

}  // namespace
}  // namespace penumbra
