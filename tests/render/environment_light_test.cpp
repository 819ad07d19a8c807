#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "../image/temp_dir.h"
#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/image/pfm.h"
#include "penumbra/render/light/environment_light.h"
#include "penumbra/render/light/light_registry.h"
#include "penumbra/render/world.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

// The documented map convention, written out independently of the light (in double): the
// map-frame direction of map point (u, v), and the pixel that a map-frame direction falls in.
Vec3 map_direction(double u, double v) {
  const double theta = kPi * v, phi = 2 * kPi * (u - 0.5);
  return {float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)),
          float(-std::sin(theta) * std::cos(phi))};
}
void map_pixel(Vec3 w, int width, int height, int& x, int& y) {
  const double u = 0.5 + std::atan2(double(w.x), -double(w.z)) / (2 * kPi);
  const double v = std::acos(std::clamp(double(w.y), -1.0, 1.0)) / kPi;
  x = std::min(int(u * width), width - 1), y = std::min(int(v * height), height - 1);
}
// Rodrigues' rotation of v by `degrees` about `axis` (right-handed).
Vec3 rotate_about(Vec3 v, Vec3 axis, double degrees) {
  const Vec3 k = normalize(axis);
  const double a = degrees * kPi / 180, c = std::cos(a), s = std::sin(a), kv = dot(k, v);
  const Vec3 kxv = cross(k, v);
  return {float(v.x * c + kxv.x * s + k.x * kv * (1 - c)),
          float(v.y * c + kxv.y * s + k.y * kv * (1 - c)),
          float(v.z * c + kxv.z * s + k.z * kv * (1 - c))};
}
// Solid angle of a pixel of row y.
double pixel_solid_angle(int y, int width, int height) {
  return 2 * kPi / width * (std::cos(kPi * y / height) - std::cos(kPi * (y + 1) / height));
}
// The documented lookup: bilinear between pixel centres, wrapping in u, clamped in v.
Rgb bilinear(const RgbImage& map, double u, double v) {
  const int w = map.width(), h = map.height();
  const double x = u * w - 0.5, y = v * h - 0.5, fx = std::floor(x), fy = std::floor(y);
  const int x0 = ((int(fx) % w) + w) % w, x1 = (x0 + 1) % w;
  const int y0 = std::clamp(int(fy), 0, h - 1), y1 = std::clamp(int(fy) + 1, 0, h - 1);
  const float tx = float(x - fx), ty = float(y - fy);
  return (map.at(x0, y0) * (1 - tx) + map.at(x1, y0) * tx) * (1 - ty) +
         (map.at(x0, y1) * (1 - tx) + map.at(x1, y1) * tx) * ty;
}
// Calls f(map-frame direction, map point u, v, solid angle) at the nodes of a quadrature over
// pixel (x, y): kSub equal steps in phi and in theta, midpoints in phi and two Gauss-Legendre
// nodes in theta (dOmega = 2 pi du * pi sin(pi v) dv). Pixel centres lie on step boundaries,
// so the bilinear interpolant is linear inside every step and the error is of order step^4.
template <class F>
void pixel_quadrature(int x, int y, int w, int h, F&& f) {
  constexpr int kSub = 16;
  const double node = 0.5 / std::sqrt(3.0);
  for (int a = 0; a < kSub; ++a)
    for (double t : {0.5 - node, 0.5 + node}) {
      const double v = (y + (a + t) / kSub) / h;
      const double d_omega = 2 * kPi / (w * kSub) * kPi * std::sin(kPi * v) * 0.5 / (kSub * h);
      for (int b = 0; b < kSub; ++b) {
        const double u = (x + (b + 0.5) / kSub) / w;
        f(map_direction(u, v), u, v, d_omega);
      }
    }
}

// A sky: a coloured gradient over a ground with black pixels, a pure blue pixel (luminance far
// below its largest channel) and a 2 x 2 sun of radiance `sun` at columns 40-41 of 64, rows 9-10.
RgbImage sky_map(int w, int h, float sun) {
  RgbImage map(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float t = (y + 0.5f) / h;
      map.at(x, y) = t < 0.5f ? Rgb(0.3f + t, 0.5f + 0.5f * t, 1.0f) * (1.0f + 0.3f * (x % 5))
                              : Rgb(0.2f, 0.15f, 0.1f) * float((x * 3 + y) % 4);  // some black
    }
  map.at(w / 8, h / 4) = Rgb(0, 0, 2);
  for (int y = 9 * h / 32; y < 11 * h / 32; ++y)
    for (int x = 40 * w / 64; x < 42 * w / 64; ++x) map.at(x, y) = Rgb(1.0f, 0.9f, 0.7f) * sun;
  return map;
}

// Monte Carlo irradiance at a point of normal n (sum of Le cos / pdf over sample_li, no
// occlusion) against the integral of Le max(0, cos) over the sphere, by quadrature over every
// pixel with the documented bilinear lookup; the map is rotated by (axis, degrees).
void expect_irradiance(const RgbImage& map, Rgb scale, Vec3 axis, double degrees, Vec3 n) {
  const EnvironmentLight light(map, scale, rotate(float(degrees), axis));
  const Vec3 n_map = rotate_about(n, axis, -degrees);
  const int w = map.width(), h = map.height();
  double ref[3] = {0, 0, 0};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      pixel_quadrature(x, y, w, h, [&](Vec3 dir, double u, double v, double d_omega) {
        const Rgb le = scale * bilinear(map, u, v);
        const double weight = std::max(0.0f, dot(n_map, dir)) * d_omega;
        for (int k = 0; k < 3; ++k) ref[k] += le[k] * weight;
      });
  constexpr int kSamples = 200000;
  Pcg32 rng(42);
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (int i = 0; i < kSamples; ++i) {
    const LightSample ls =
        light.sample_li({0.3f, 0.1f, -0.2f}, {rng.next_float(), rng.next_float()});
    ASSERT_GT(ls.pdf, 0.0f);
    const double c = std::max(0.0f, dot(n, ls.wi));
    for (int k = 0; k < 3; ++k) {
      const double f = ls.li[k] * c / ls.pdf;
      sum[k] += f, sum2[k] += f * f;
    }
  }
  for (int k = 0; k < 3; ++k) {
    const double mean = sum[k] / kSamples;
    const double sigma = std::sqrt(std::max(0.0, sum2[k] / kSamples - mean * mean) / kSamples);
    // Four standard deviations of the mean, plus the quadrature's error (far smaller).
    EXPECT_NEAR(mean, ref[k], 4 * sigma + 1e-5 * ref[k]) << "channel " << k << ", sigma " << sigma;
  }
}

// With a small sun 3000 times brighter than the sky (most of the irradiance), straight up and
// tilted towards and away from the sun.
TEST(EnvironmentLight, IrradianceMatchesQuadratureOfTheMap) {
  const RgbImage map = sky_map(64, 32, 3000.0f);
  expect_irradiance(map, Rgb(1.0f, 0.8f, 1.2f), {0, 1, 0}, 0, {0, 1, 0});
  expect_irradiance(map, Rgb(1.0f), {0, 1, 0}, 0, normalize(Vec3{0.5f, 0.4f, 0.3f}));
  expect_irradiance(map, Rgb(1.0f), {0, 1, 0}, 0, normalize(Vec3{-0.6f, -0.2f, 0.5f}));
}

TEST(EnvironmentLight, IrradianceOfARotatedMapMatchesQuadrature) {
  const RgbImage map = sky_map(64, 32, 3000.0f);
  expect_irradiance(map, Rgb(0.5f, 1.0f, 2.0f), {1, 1, 0}, 70, {0, 1, 0});
  expect_irradiance(map, Rgb(1.0f), {0.2f, -1, 0.5f}, -130, normalize(Vec3{0.3f, 0.2f, -0.9f}));
}

// Sampled directions fall in each pixel with probability (integral of luminance(Le) over the
// pixel) / (integral over the sphere), the pixel's share of the luminance integral, computed by
// quadrature of the documented bilinear Le; each reports that share over the pixel's solid angle.
TEST(EnvironmentLight, SampledDirectionsPassAChiSquareTestAgainstTheLuminance) {
  constexpr int kW = 32, kH = 16, kSamples = 1000000;
  const Rgb scale(0.5f, 1.0f, 2.0f);
  const Vec3 axis{0.3f, 1, -0.4f};
  const double degrees = 35;
  RgbImage map = sky_map(kW, kH, 200.0f);
  for (int y = 12; y < kH; ++y)  // a black band: rows 13 to 15 are out of the interpolation's reach
    for (int x = 0; x < kW; ++x) map.at(x, y) = Rgb(0.0f);
  const EnvironmentLight light(map, scale, rotate(float(degrees), axis));
  std::vector<double> expected(kW * kH), observed(kW * kH, 0.0);
  double total = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      double e = 0;  // the integral of luminance(Le) over the pixel
      pixel_quadrature(x, y, kW, kH, [&](Vec3, double u, double v, double d_omega) {
        e += (scale * bilinear(map, u, v)).luminance() * d_omega;
      });
      total += expected[y * kW + x] = e;
    }
  Pcg32 rng(5);
  int pdf_mismatches = 0;
  for (int i = 0; i < kSamples; ++i) {
    const LightSample ls = light.sample_li({}, {rng.next_float(), rng.next_float()});
    int x, y;
    map_pixel(rotate_about(ls.wi, axis, -degrees), kW, kH, x, y);
    observed[y * kW + x] += 1;
    const double pdf = expected[y * kW + x] / total / pixel_solid_angle(y, kW, kH);
    if (std::fabs(ls.pdf - pdf) > 1e-4 * pdf) ++pdf_mismatches;  // only by rounding on an edge
  }
  EXPECT_LE(pdf_mismatches, kSamples / 10000);
  // Pearson's statistic; black pixels must stay (all but) empty, bins expecting under 5 are pooled.
  double chi2 = 0, pooled_expected = 0, pooled_observed = 0, black = 0;
  int dof = -1;
  for (int i = 0; i < kW * kH; ++i) {
    const double e = expected[i] / total * kSamples;
    if (e == 0)
      black += observed[i];
    else if (e < 5)
      pooled_expected += e, pooled_observed += observed[i];
    else
      chi2 += (observed[i] - e) * (observed[i] - e) / e, ++dof;
  }
  if (pooled_expected > 0)
    chi2 +=
        (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected,
        ++dof;
  EXPECT_EQ(dof, kW * (kH - 3) - 1);  // every pixel but the black band's last three rows
  EXPECT_LE(black, kSamples / 100000);
  // Chi-square of k degrees of freedom: mean k, variance 2k; six deviations above the mean.
  RecordProperty("chi2", std::to_string(chi2) + " dof " + std::to_string(dof));
  EXPECT_LT(chi2, dof + 6 * std::sqrt(2.0 * dof));
}

// pdf_li is exactly the density sample_li reports, and le along the sampled direction is li;
// pdf_le agrees with sample_le.
TEST(EnvironmentLight, PdfLiEqualsTheSamplePdf) {
  EnvironmentLight light(sky_map(64, 32, 3000.0f), Rgb(1.0f), rotate(50, {1, 2, 3}));
  light.preprocess(Bounds3({-1, 0, -2}, {3, 1, 2}));
  Pcg32 rng(9);
  const Vec3 p{0.5f, 0.5f, 0.5f};
  for (int i = 0; i < 50000; ++i) {
    const LightSample ls = light.sample_li(p, {rng.next_float(), rng.next_float()});
    ASSERT_NEAR(length(ls.wi), 1.0f, 1e-5f);
    ASSERT_TRUE(ls.pdf > 0 && std::isfinite(ls.pdf) && !ls.delta && ls.distance == kInfinity);
    ASSERT_EQ(light.pdf_li(p, ls.wi, {}), ls.pdf);
    ASSERT_EQ(light.le(Ray{p, ls.wi}), ls.li);
    const LightLeSample le = light.sample_le({rng.next_float(), rng.next_float()},
                                             {rng.next_float(), rng.next_float()}, 0);
    float pdf_pos = 0, pdf_dir = 0;
    light.pdf_le(le.ray, {}, pdf_pos, pdf_dir);
    ASSERT_EQ(pdf_dir, le.pdf_dir);
    ASSERT_EQ(pdf_pos, le.pdf_pos);
    ASSERT_EQ(light.le(Ray{p, -le.ray.d}), le.l);
  }
}

// A constant map is sampled uniformly, also inside each pixel: density 1 / (4 pi) in every
// direction, and samples spread evenly over 16 x 16 bins of equal solid angle (equal steps in
// world-frame y and azimuth), whose boundaries cut across the 4 x 2 map's pixels.
TEST(EnvironmentLight, ConstantMapHasUniformPdf) {
  constexpr int kBins = 16, kSamples = 200000;
  for (float degrees : {0.0f, 33.0f}) {
    const EnvironmentLight light(RgbImage(4, 2, Rgb(0.7f, 0.3f, 0.1f)), Rgb(2.0f),
                                 rotate(degrees, {1, 0, 1}));
    Pcg32 rng(1);
    const float uniform = float(1 / (4 * kPi));
    std::vector<double> observed(kBins * kBins, 0.0);
    for (int i = 0; i < kSamples; ++i) {
      const LightSample ls = light.sample_li({}, {rng.next_float(), rng.next_float()});
      ASSERT_NEAR(ls.pdf, uniform, 1e-5f * uniform);
      ASSERT_EQ(ls.li, Rgb(1.4f, 0.6f, 0.2f));
      const Vec3 w = normalize(
          Vec3{rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f});
      ASSERT_NEAR(light.pdf_li({}, w, {}), uniform, 1e-5f * uniform);
      const int by = std::min(int((ls.wi.y + 1) / 2 * kBins), kBins - 1);
      const double azimuth = std::atan2(double(ls.wi.x), double(ls.wi.z)) / (2 * kPi) + 0.5;
      observed[by * kBins + std::min(int(azimuth * kBins), kBins - 1)] += 1;
    }
    // Chi-square of k = 255 degrees of freedom: mean k, variance 2k; six deviations above.
    const double e = double(kSamples) / (kBins * kBins);
    double chi2 = 0;
    for (double o : observed) chi2 += (o - e) * (o - e) / e;
    const int dof = kBins * kBins - 1;
    EXPECT_LT(chi2, dof + 6 * std::sqrt(2.0 * dof)) << degrees << " degrees";
  }
}

// "environment" with only a radiance is a constant environment: Le = radiance from every
// direction, density 1 / (4 pi), and power 4 pi * pi r^2 * L for the bounding sphere's radius r.
TEST(EnvironmentLight, WithoutAMapItIsAConstantEnvironment) {
  const SceneParams params({{"type", "environment"}, {"radiance", {1, 2, 3}}}, "s.json",
                           "/lights/0");
  EnvironmentLight env(params);
  const Bounds3 b({-1, -2, 0}, {4, 1, 1});
  env.preprocess(b);
  const double r = 0.5 * std::sqrt(5.0 * 5.0 + 3.0 * 3.0 + 1.0 * 1.0);
  const float pdf = float(1.0 / (4.0 * std::numbers::pi));
  Pcg32 rng(2);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 w =
        normalize(Vec3{rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f});
    EXPECT_EQ(env.le(Ray{{}, w}), Rgb(1, 2, 3));
    EXPECT_NEAR(env.pdf_li({}, w, {}), pdf, 1e-8f);
    const LightSample ls = env.sample_li({}, {rng.next_float(), rng.next_float()});
    EXPECT_NEAR(ls.pdf, pdf, 1e-8f);
    EXPECT_EQ(ls.li, Rgb(1, 2, 3));
  }
  for (int k = 0; k < 3; ++k) {
    const double power = 4.0 * std::numbers::pi * std::numbers::pi * r * r * double(k + 1);
    EXPECT_NEAR(env.power()[k], power, 1e-5 * power);
  }
}

// Expects a and b equal per channel within `tolerance`.
void expect_rgb_near(Rgb a, Rgb b, float tolerance, const std::string& what) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], tolerance) << what << ", channel " << k;
}

// A map whose every pixel differs: the direction of each pixel's centre looks up that pixel
// (up to rounding of the interpolation weights), without and with a rotation.
TEST(EnvironmentLight, PixelCentresLookUpTheirPixels) {
  constexpr int kW = 8, kH = 4;
  RgbImage map(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) map.at(x, y) = Rgb(float(x), float(y), float(1 + x + kW * y));
  const Vec3 axis{1, -2, 0.5f};
  for (double degrees : {0.0, 100.0}) {
    const EnvironmentLight light(map, Rgb(1, 2, 3), rotate(float(degrees), axis));
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const Vec3 w = rotate_about(map_direction((x + 0.5) / kW, (y + 0.5) / kH), axis, degrees);
        expect_rgb_near(light.le(Ray{{5, 5, 5}, w}), Rgb(1, 2, 3) * map.at(x, y), 1e-3f,
                        std::to_string(x) + ", " + std::to_string(y));
      }
  }
}

// Writes `map` as a PFM in `dir` and returns the path.
std::string write_map(const test::TempDir& dir, const RgbImage& map, const std::string& name) {
  const std::string path = dir.file(name);
  write_pfm(map, path);
  return path;
}

// The direction at `azimuth` degrees from -z towards +x and `elevation` degrees above the horizon.
Vec3 sky_direction(double azimuth, double elevation) {
  const double a = azimuth * kPi / 180, e = elevation * kPi / 180;
  return {float(std::cos(e) * std::sin(a)), float(std::sin(e)), float(-std::cos(e) * std::cos(a))};
}

// The documented orientation, read through a scene's parameters: the image's top row is +y, its
// centre column looks along -z, the column at u = 0.75 along +x, the left and right edges meet
// at +z; "transform" rotates it. An 8 x 4 map of pixels (x, y, 0) has its pixel centres every
// 45 degrees of azimuth and elevation, from 22.5 degrees.
TEST(EnvironmentLight, MapTopIsUpAndItsCentreLooksAlongMinusZ) {
  constexpr int kW = 8, kH = 4;
  RgbImage map(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) map.at(x, y) = Rgb(float(x), float(y), 0);
  const test::TempDir dir;
  const std::string path = write_map(dir, map, "m.pfm");
  const EnvironmentLight plain(
      SceneParams({{"type", "environment"}, {"map", path}}, "s.json", "/l"));
  const auto le = [](const EnvironmentLight& light, double azimuth, double elevation) {
    return light.le(Ray{{}, sky_direction(azimuth, elevation)});
  };
  EXPECT_NEAR(le(plain, 10, 90).g, 0, 1e-6f);        // zenith: row 0
  EXPECT_NEAR(le(plain, 10, -90).g, kH - 1, 1e-6f);  // nadir: the bottom row
  expect_rgb_near(le(plain, 22.5, 22.5), Rgb(4, 1, 0), 1e-3f, "just right of -z, above");
  expect_rgb_near(le(plain, -22.5, -22.5), Rgb(3, 2, 0), 1e-3f, "just left of -z, below");
  expect_rgb_near(le(plain, 112.5, 22.5), Rgb(6, 1, 0), 1e-3f, "just past +x");
  expect_rgb_near(le(plain, 180, 22.5), Rgb(3.5f, 1, 0), 1e-3f, "+z: the seam, columns 7 and 0");
  // Rotated 90 degrees about +y, (x, y, z) -> (z, y, -x): azimuths decrease by 90 degrees.
  const nlohmann::json rotation = {{{"rotate", {{"axis", {0, 1, 0}}, {"angle", 90}}}}};
  const EnvironmentLight turned(SceneParams(
      {{"type", "environment"}, {"map", path}, {"transform", rotation}}, "s.json", "/l"));
  expect_rgb_near(le(turned, 22.5 - 90, 22.5), Rgb(4, 1, 0), 1e-3f, "rotated");
  expect_rgb_near(le(turned, 112.5 - 90, 22.5), Rgb(6, 1, 0), 1e-3f, "rotated +x");
}

// Photons: E[beta] of sample_le is the power, pi r^2 times the integral of Le over the sphere; the
// rays pass through the bounding sphere.
TEST(EnvironmentLight, EmittedRaysCarryThePower) {
  EnvironmentLight light(sky_map(64, 32, 3000.0f), Rgb(1, 0.5f, 2), rotate(20, {0, 0, 1}));
  const Bounds3 b({-1, 0, -2}, {3, 1, 2});
  light.preprocess(b);
  const Vec3 center = b.center();
  const float radius = length(b.hi - center);
  constexpr int kSamples = 200000;
  Pcg32 rng(13);
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (int i = 0; i < kSamples; ++i) {
    const LightLeSample s = light.sample_le({rng.next_float(), rng.next_float()},
                                            {rng.next_float(), rng.next_float()}, 0.5f);
    ASSERT_NEAR(s.pdf_pos, 1 / (kPi * radius * radius), 1e-5 / (radius * radius));
    const Vec3 to_center = center - s.ray.o;
    const float along = dot(to_center, s.ray.d);
    ASSERT_GT(along, 0.999f * radius);  // starts one radius before the centre, heading in
    ASSERT_LE(length(to_center - s.ray.d * along), radius * 1.0001f);
    const Rgb beta = s.beta();
    for (int k = 0; k < 3; ++k) sum[k] += beta[k], sum2[k] += double(beta[k]) * beta[k];
  }
  const Rgb power = light.power();
  for (int k = 0; k < 3; ++k) {
    const double mean = sum[k] / kSamples;
    const double sigma = std::sqrt(std::max(0.0, sum2[k] / kSamples - mean * mean) / kSamples);
    EXPECT_NEAR(mean, power[k], 4 * sigma + 1e-5 * power[k]) << "channel " << k;
  }
}

// Each bad parameter is an InputError naming the scene file, the JSON path and the problem.
TEST(EnvironmentLight, BadParametersNameTheFileAndJsonPath) {
  const test::TempDir dir;
  const std::string good = write_map(dir, RgbImage(4, 2, Rgb(1)), "good.pfm");
  RgbImage nan_map(4, 2, Rgb(1));
  nan_map.at(3, 1).g = std::nanf("");
  const std::string bad_pixel = write_map(dir, nan_map, "nan.pfm");
  test::write_bytes(dir.file("garbage.pfm"), "this is not a PFM file");
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
  expect_error({{"map", dir.file("missing.pfm")}}, "/map", "not found");
  expect_error({{"map", dir.file("garbage.pfm")}}, "/map", "not a PFM file");
  expect_error({{"map", bad_pixel}}, "/map", "pixel (3, 1) is not finite");
  expect_error({{"map", dir.file("sky.png")}}, "/map", ".exr or .pfm");
  expect_error({{"map", ""}}, "/map", "must not be empty");
  expect_error({{"map", good}, {"radiance", {1, -1, 1}}}, "/radiance", "non-negative");
  expect_error({{"map", good}, {"transform", {{{"scale", 2}}}}}, "/transform", "rotation");
  expect_error({{"transform", {{{"translate", {0, 1, 0}}}}}}, "/transform", "translation");
  expect_error({{"transform", {{{"rotate", {{"angle", 5}}}}}}}, "/transform/0/rotate", "axis");
  expect_error({{"map", good}, {"maps", good}}, "/maps", "unknown key");
}

// A scene file's relative "map" is found next to the scene file, wherever the program runs.
TEST(EnvironmentLight, SceneLoaderResolvesTheMapRelativeToTheSceneFile) {
  const test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "maps");
  write_map(dir, RgbImage(4, 2, Rgb(0.25f, 0.5f, 0.75f)), "maps/flat.pfm");
  test::write_bytes(dir.file("scene.json"), R"({
    "camera": {"type": "pinhole"},
    "lights": [{"type": "environment", "map": "maps/flat.pfm", "radiance": 2}],
    "shapes": []})");
  const SceneDesc desc = load_scene(dir.file("scene.json"));
  ASSERT_EQ(desc.lights.size(), 1u);
  const EnvironmentLight light(desc.lights[0]);
  EXPECT_EQ(light.le(Ray{{}, {0, 1, 0}}), Rgb(0.5f, 1.0f, 1.5f));
}

// "environment" is a registered light type; the world lists it as infinite and rays that leave the
// scene see it.
TEST(EnvironmentLight, IsRegisteredAndLightsEscapingRays) {
  const SceneDesc desc = parse_scene(R"({
    "camera": {"type": "pinhole", "position": [0, 0, -3], "look_at": [0, 0, 0]},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "lights": [{"type": "environment", "radiance": [0.5, 1, 2]}],
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})",
                                     "env.json", "");
  const World world(desc, "brute");
  ASSERT_EQ(world.infinite_lights().size(), 1u);
  EXPECT_EQ(world.infinite_lights()[0]->kind(), LightKind::kInfinite);
  EXPECT_EQ(world.escaped(Ray{{0, 0, 5}, {0, 1, 0}}), Rgb(0.5f, 1, 2));
  const auto types = light_types();
  EXPECT_NE(std::find(types.begin(), types.end(), "environment"), types.end());
}

}  // namespace
}  // namespace penumbra
