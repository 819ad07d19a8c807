// The equal-area octahedral mapping and environment maps in that layout (pbrt-v4's image infinite
// lights), read directly and through the pbrt importer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "../image/temp_dir.h"
#include "chi_square.h"
#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/geometry/sphere_direction.h"
#include "penumbra/image/pfm.h"
#include "penumbra/render/light/environment_light.h"
#include "penumbra/render/sampling/equal_area.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

Vec3 random_direction(Pcg32& rng) {
  return sample_uniform_sphere({rng.next_float(), rng.next_float()});
}

TEST(EqualArea, RoundTripsDirectionsAndSquarePoints) {
  Pcg32 rng(7);
  for (int i = 0; i < 100000; ++i) {
    const Vec3 d = random_direction(rng);
    const Vec3 back = equal_area_square_to_sphere(equal_area_sphere_to_square(d));
    ASSERT_LT(length(back - d), 2e-5f) << d.x << " " << d.y << " " << d.z;
    const Vec2 p{rng.next_float(), rng.next_float()};
    const Vec2 q = equal_area_sphere_to_square(equal_area_square_to_sphere(p));
    ASSERT_LT(std::fabs(q.x - p.x) + std::fabs(q.y - p.y), 4e-5f) << p.x << " " << p.y;
  }
}

// The centre is +z, the four corners -z, the diamond's vertices (edge midpoints) the equator's
// +-x and +-y; the edges fold at their midpoints.
TEST(EqualArea, CentreIsPlusZCornersMinusZAndEdgesFold) {
  const auto near = [](Vec3 a, Vec3 b) { return length(a - b) < 1e-6f; };
  EXPECT_TRUE(near(equal_area_square_to_sphere({0.5f, 0.5f}), {0, 0, 1}));
  for (Vec2 c : {Vec2{0, 0}, Vec2{1, 0}, Vec2{0, 1}, Vec2{1, 1}})
    EXPECT_TRUE(near(equal_area_square_to_sphere(c), {0, 0, -1}));
  EXPECT_TRUE(near(equal_area_square_to_sphere({1.0f, 0.5f}), {1, 0, 0}));
  EXPECT_TRUE(near(equal_area_square_to_sphere({0.0f, 0.5f}), {-1, 0, 0}));
  EXPECT_TRUE(near(equal_area_square_to_sphere({0.5f, 1.0f}), {0, 1, 0}));
  EXPECT_TRUE(near(equal_area_square_to_sphere({0.5f, 0.0f}), {0, -1, 0}));
  for (float t : {0.05f, 0.2f, 0.37f, 0.49f}) {
    EXPECT_TRUE(near(equal_area_square_to_sphere({0, t}), equal_area_square_to_sphere({0, 1 - t})));
    EXPECT_TRUE(near(equal_area_square_to_sphere({1, t}), equal_area_square_to_sphere({1, 1 - t})));
    EXPECT_TRUE(near(equal_area_square_to_sphere({t, 0}), equal_area_square_to_sphere({1 - t, 0})));
    EXPECT_TRUE(near(equal_area_square_to_sphere({t, 1}), equal_area_square_to_sphere({1 - t, 1})));
  }
}

// Equal area: the cell centres of an n x n grid over the square fall into any cap z > c and any
// azimuth wedge in proportion to its solid angle (up to the cells the boundary cuts: O(1/n)).
TEST(EqualArea, PreservesArea) {
  constexpr int kN = 1024;
  const std::vector<double> caps = {-0.9, -0.5, -0.1, 0.0, 0.3, 0.7, 0.95};
  std::vector<double> in_cap(caps.size(), 0.0), in_wedge(8, 0.0);
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      const Vec3 d = equal_area_square_to_sphere({(i + 0.5f) / kN, (j + 0.5f) / kN});
      for (size_t k = 0; k < caps.size(); ++k) in_cap[k] += d.z > caps[k];
      const double phi = std::atan2(double(d.y), double(d.x)) + kPi;  // in [0, 2 pi]
      in_wedge[std::min(7, int(phi / (2 * kPi) * 8))] += 1;
    }
  const double total = double(kN) * kN;
  for (size_t k = 0; k < caps.size(); ++k)
    EXPECT_NEAR(in_cap[k] / total, (1 - caps[k]) / 2, 4.0 / kN) << "cap z > " << caps[k];
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(in_wedge[k] / total, 1.0 / 8, 4.0 / kN) << "wedge " << k;
}

// A map whose texels hold f at their centres' directions.
template <class F>
RgbImage octahedral_map(int n, F&& f) {
  RgbImage map(n, n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      map.at(x, y) = f(equal_area_square_to_sphere({(x + 0.5f) / n, (y + 0.5f) / n}));
  return map;
}

// A sky with a bright lobe around +z and a dimmer one in the lower hemisphere near a corner fold.
Rgb lobes(Vec3 d) {
  const float up = std::pow(std::fmax(0.0f, dot(d, normalize(Vec3{0.3f, 0.2f, 1.0f}))), 8.0f);
  const float low = std::pow(std::fmax(0.0f, dot(d, normalize(Vec3{-1.0f, 0.6f, -0.9f}))), 4.0f);
  return Rgb(0.05f + 20 * up + 2 * low, 0.1f + 10 * up + 3 * low, 0.2f + 5 * up + low);
}

// The integral of Le over each pixel, by the midpoint rule on a k x k grid of sub-cells: exact
// for the bilinear interpolant, whose pieces end at pixel centres (sub-cell boundaries for even
// k), as the map is equal area (every sub-cell has the solid angle 4 pi / (n k)^2).
std::vector<double> pixel_integrals(const EnvironmentLight& light, int n) {
  constexpr int kSub = 4;
  std::vector<double> out(size_t(n) * n, 0.0);
  const double d_omega = 4 * kPi / (double(n) * n * kSub * kSub);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int b = 0; b < kSub; ++b)
        for (int a = 0; a < kSub; ++a) {
          const Vec2 p{(x + (a + 0.5f) / kSub) / n, (y + (b + 0.5f) / kSub) / n};
          out[size_t(y) * n + x] +=
              light.le(Ray{{}, equal_area_square_to_sphere(p)}).luminance() * d_omega;
        }
  return out;
}

// Sampled directions fall into pixels in proportion to the integral of Le's luminance there.
TEST(EnvironmentOctahedral, SampledDirectionsPassAChiSquareTestAgainstTheLuminance) {
  constexpr int kN = 32, kSamples = 400000;
  const EnvironmentLight light(octahedral_map(kN, lobes), Rgb(1.0f), {}, true);
  const std::vector<double> weight = pixel_integrals(light, kN);
  double sum = 0;
  for (double w : weight) sum += w;
  std::vector<double> observed(weight.size(), 0.0), expected(weight.size());
  for (size_t i = 0; i < weight.size(); ++i) expected[i] = kSamples * weight[i] / sum;
  Pcg32 rng(11);
  for (int i = 0; i < kSamples; ++i) {
    const LightSample ls = light.sample_li({}, {rng.next_float(), rng.next_float()});
    const Vec2 p = equal_area_sphere_to_square(ls.wi);
    observed[size_t(std::min(int(p.y * kN), kN - 1)) * kN + std::min(int(p.x * kN), kN - 1)] += 1;
  }
  EXPECT_TRUE(test::chi_square(observed, expected));
  // The light's own integral is the same sum of exact pixel integrals.
  EXPECT_NEAR(light.integral().luminance(), sum, 1e-4 * sum);
}

// pdf_li is the sample's density and integrates to one over the sphere; Le / pdf averages to the
// integral of Le.
TEST(EnvironmentOctahedral, DensityIsConsistentAndNormalised) {
  const EnvironmentLight light(octahedral_map(24, lobes), Rgb(1.0f, 0.5f, 2.0f), {}, true);
  constexpr int kSamples = 200000;
  Pcg32 rng(3);
  double pdf_sum = 0, pdf_sum2 = 0, est[3] = {0, 0, 0}, est2[3] = {0, 0, 0};
  for (int i = 0; i < kSamples; ++i) {
    const LightSample ls = light.sample_li({}, {rng.next_float(), rng.next_float()});
    ASSERT_GT(ls.pdf, 0.0f);
    ASSERT_FLOAT_EQ(ls.pdf, light.pdf_li({}, ls.wi, {}));
    for (int k = 0; k < 3; ++k) {
      const double f = ls.li[k] / ls.pdf;
      est[k] += f, est2[k] += f * f;
    }
    const double q = 4 * kPi * light.pdf_li({}, random_direction(rng), {});
    pdf_sum += q, pdf_sum2 += q * q;
  }
  const auto check = [](double sum, double sum2, double expected, const char* what) {
    const double mean = sum / kSamples;
    const double sigma = std::sqrt(std::max(0.0, sum2 / kSamples - mean * mean) / kSamples);
    EXPECT_NEAR(mean, expected, 4 * sigma + 1e-6 * expected) << what << ", sigma " << sigma;
  };
  check(pdf_sum, pdf_sum2, 1.0, "4 pi E[pdf] over uniform directions");
  for (int k = 0; k < 3; ++k) check(est[k], est2[k], light.integral()[k], "E[Le / pdf]");
}

// Le follows the mapped function everywhere, also next to the folded edges and the corners,
// where the bilinear lookup takes its neighbours from across the fold (without the fold a lookup
// there mixes texels of distant directions). The bound is the interpolation error of f = 1 + x +
// 2 y - z over a pixel: |f| changes by at most |grad f| times a pixel's angular size, twice the
// mean size 2 sqrt(pi) / n near the folds, and the bilinear error is below an eighth of that.
TEST(EnvironmentOctahedral, LookupIsSmoothAcrossTheFoldedEdges) {
  constexpr int kN = 64;
  const auto f = [](Vec3 d) { return Rgb(2.5f + d.x + 2 * d.y - d.z); };
  const EnvironmentLight light(octahedral_map(kN, f), Rgb(1.0f), {}, true);
  const double bound = std::sqrt(6.0) * 2 * 2 * std::sqrt(kPi) / kN / 8 * 2;
  Pcg32 rng(5);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    // Points within a pixel of an edge of the square (all in the lower hemisphere).
    const float t = rng.next_float(), s = rng.next_float() * (1.0f / kN);
    const int edge = i % 4;
    const Vec2 p = edge == 0   ? Vec2{s, t}
                   : edge == 1 ? Vec2{1 - s, t}
                   : edge == 2 ? Vec2{t, s}
                               : Vec2{t, 1 - s};
    const Vec3 d = equal_area_square_to_sphere(p);
    worst = std::max(worst, double(std::fabs(light.le(Ray{{}, d}).r - f(d).r)));
  }
  EXPECT_LT(worst, bound);
}

// JSON "mapping": unknown names and non-square octahedral maps are refused at the parameter.
TEST(EnvironmentOctahedral, BadMappingsNameTheParameter) {
  const test::TempDir dir;
  write_pfm(RgbImage(8, 4, Rgb(1)), dir.file("wide.pfm"));
  const auto expect_error = [](nlohmann::json params, const std::string& path,
                               const std::string& problem) {
    params["type"] = "environment";
    try {
      EnvironmentLight light(SceneParams(params, "scene.json", "/lights/0"));
      ADD_FAILURE() << "no error for " << params.dump();
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("scene.json:/lights/0" + path), std::string::npos) << what;
      EXPECT_NE(what.find(problem), std::string::npos) << what;
    }
  };
  expect_error({{"map", dir.file("wide.pfm")}, {"mapping", "octahedral"}}, "/map", "square");
  expect_error({{"mapping", "cube"}}, "/mapping", "unknown mapping");
}

// pbrt-v4: `LightSource "infinite" "string filename"` reads the map as an equal-area octahedral
// square in the light's frame. Under `Rotate -90 1 0 0` (pbrt's z-up sky turned y-up) the map's
// centre (+z) lies along world +y, also after the importer's x mirror.
TEST(EnvironmentOctahedral, PbrtInfiniteLightMapIsOctahedralInTheLightFrame) {
  const test::TempDir dir;
  constexpr int kN = 16;
  RgbImage map(kN, kN, Rgb(0.0f));
  for (int y = kN / 2 - 1; y <= kN / 2; ++y)
    for (int x = kN / 2 - 1; x <= kN / 2; ++x) map.at(x, y) = Rgb(100.0f);
  write_pfm(map, dir.file("sky.pfm"));
  test::write_bytes(dir.file("scene.pbrt"), R"(LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
AttributeBegin
  Rotate -90 1 0 0
  LightSource "infinite" "string filename" "sky.pfm" "float scale" 2
AttributeEnd
)");
  const SceneDesc desc = load_scene(dir.file("scene.pbrt"));
  ASSERT_EQ(desc.lights.size(), 1u);
  const EnvironmentLight light(desc.lights[0]);
  EXPECT_TRUE(light.octahedral());
  EXPECT_FLOAT_EQ(light.le(Ray{{}, {0, 1, 0}}).r, 200.0f);
  EXPECT_FLOAT_EQ(light.le(Ray{{}, {0, -1, 0}}).r, 0.0f);
  Pcg32 rng(9);
  for (int i = 0; i < 1000; ++i) {
    const LightSample ls = light.sample_li({}, {rng.next_float(), rng.next_float()});
    // Only pixels 5-10 of each axis have light in their bilinear footprint: |U|, |V| <= 0.375 on
    // the [-1, 1]^2 square, so r = |U| + |V| <= 0.75 and the cap is y >= 1 - 0.75^2 = 0.4375.
    ASSERT_GT(ls.wi.y, 0.437f);
  }
  test::write_bytes(dir.file("missing.pbrt"), R"(WorldBegin
LightSource "infinite" "string filename" "nowhere.exr"
)");
  try {
    (void)load_scene(dir.file("missing.pbrt"));
    ADD_FAILURE() << "no error for a missing map";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.pbrt:2:1: infinite light map not found"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace penumbra
