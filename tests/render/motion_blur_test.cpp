/// Motion blur: the camera's shutter gives ray times uniform over [open, close], stratified with
/// the sampler; a moving sphere leaves the smear that the shutter interval predicts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/render/camera/thin_lens_camera.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// A camera description with `extra` JSON keys.
SceneParams camera_params(const std::string& type, const std::string& extra) {
  return SceneParams(
      nlohmann::json::parse(fmt::format(
          R"({{"type": "{}", "position": [0, 0, 0], "look_at": [0, 0, 1]{}}})", type, extra)),
      "test.json", "/camera");
}

// Ray times are the shutter's affine image of the time sample: open at u = 0, never past close,
// for both camera types; the default shutter [0, 0] gives time 0.
TEST(Shutter, RayTimesSpanTheShutterInterval) {
  for (const char* type : {"pinhole", "thin_lens"}) {
    const std::string lens = std::string(type) == "thin_lens" ? R"(, "focus_distance": 2)" : "";
    const auto cam = make_camera(camera_params(type, lens + R"(, "shutter": [0.2, 0.7])"), 8, 8);
    for (int i = 0; i <= 1000; ++i) {
      const float u = i == 1000 ? 0x1.fffffep-1f : float(i) / 1000.0f;
      const float t = cam->generate_ray({{4, 4}, {0.5f, 0.5f}, u}).time;
      EXPECT_NEAR(t, 0.2f + 0.5f * u, 1e-6f) << type;
      EXPECT_GE(t, 0.2f);
      EXPECT_LE(t, 0.7f);
    }
    EXPECT_EQ(cam->generate_ray({{4, 4}, {0.5f, 0.5f}, 0.0f}).time, 0.2f);
    const auto still = make_camera(camera_params(type, lens), 8, 8);
    EXPECT_EQ(still->generate_ray({{4, 4}, {0.5f, 0.5f}, 0.7f}).time, 0.0f) << type;
  }
}

TEST(Shutter, BadIntervalsAreErrorsNamingTheKey) {
  const auto error = [](const std::string& extra) {
    try {
      make_camera(camera_params("pinhole", extra), 8, 8);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error(R"(, "shutter": [1, 0.5])")
                .find("test.json:/camera/shutter: the shutter must "
                      "open before it closes"),
            std::string::npos)
      << error(R"(, "shutter": [1, 0.5])");
  EXPECT_NE(error(R"(, "shutter": [0])").find("/camera/shutter: expected an array of 2 numbers"),
            std::string::npos);
  EXPECT_NE(error(R"(, "shutter": [0, "1"])").find("/camera/shutter/1"), std::string::npos);
  EXPECT_NE(error(R"(, "shuter": [0, 1])").find("/camera/shuter: unknown key"), std::string::npos);
}

/// Returns each camera ray's time as its radiance and keeps every time it saw.
class TimeIntegrator final : public SamplingIntegrator {
 public:
  std::string name() const override { return "time"; }
  Rgb li(const Ray& ray, Sampler&, RayCounter&) const override {
    const std::lock_guard lock(mutex_);
    times_.push_back(ray.time);
    return Rgb(ray.time);
  }
  std::vector<float> times() const { return times_; }

 private:
  mutable std::mutex mutex_;
  mutable std::vector<float> times_;
};

/// The times of the camera rays of a w x h render with `sampler` at `spp`, shutter [open, close].
std::vector<float> render_times(const std::string& sampler, int w, int h, int spp, float open,
                                float close) {
  RenderJob job(test::scene_from_text(fmt::format(
      R"({{"camera": {{"type": "pinhole", "position": [0, 0, 0], "look_at": [0, 0, 1]}},
          "render": {{"resolution": [{}, {}], "spp": {}, "seed": 7, "sampler": "{}"}},
          "materials": {{"m": {{"type": "diffuse"}}}},
          "shapes": [{{"type": "sphere", "center": [0, 0, 5], "radius": 1, "material": "m"}}]}})",
      w, h, spp, sampler)));
  auto camera = std::make_unique<PinholeCamera>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, Vec3{0, 1, 0}, 45.0f,
                                                w, h);
  camera->set_shutter({open, close});
  job.camera = std::move(camera);
  auto integrator = std::make_unique<TimeIntegrator>();
  const TimeIntegrator& ti = *integrator;
  job.integrator = std::move(integrator);
  job.run();
  return ti.times();
}

// Through the render loop: the times of 4096 independent camera rays are uniform over the
// shutter by the Kolmogorov-Smirnov test (critical value 1.95 / sqrt(n): level 0.1%).
TEST(Shutter, RenderedRayTimesAreUniformOverTheShutter) {
  std::vector<float> t = render_times("independent", 64, 64, 1, -0.5f, 1.5f);
  ASSERT_EQ(t.size(), 4096u);
  std::sort(t.begin(), t.end());
  double d = 0;
  const double n = double(t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    const double f = (double(t[i]) + 0.5) / 2.0;  // the uniform CDF on [-0.5, 1.5]
    d = std::max({d, std::fabs(f - double(i) / n), std::fabs(double(i + 1) / n - f)});
  }
  EXPECT_LT(d, 1.95 / std::sqrt(n));
  EXPECT_GE(t.front(), -0.5f);
  EXPECT_LE(t.back(), 1.5f);
}

// With the jittered sampler the time dimension is stratified: each of a pixel's 64 samples falls
// in its own 1/64 of the shutter.
TEST(Shutter, JitteredTimesFallOneInEachStratum) {
  std::vector<float> t = render_times("jittered", 1, 1, 64, 0.0f, 2.0f);
  ASSERT_EQ(t.size(), 64u);
  std::sort(t.begin(), t.end());
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_GE(t[i], 2.0f * float(i) / 64.0f) << i;
    EXPECT_LT(t[i], 2.0f * float(i + 1) / 64.0f) << i;
  }
}

/// The smear scene: a pinhole at the origin looking along +z (vfov 2 atan(0.008), 96 x 16 pixels,
/// so one pixel is 0.1 units at depth 100) and a white sphere of radius 0.5 (5 pixels) at depth
/// 100 moving from x = 2 to x = -2 (40 pixels to the right in the image) between times 0 and 1.
constexpr int kW = 96, kH = 16;
constexpr double kTanHalf = 0.008, kRadius = 0.5, kDepth = 100, kY = 0.05;
constexpr double kX0 = 2, kX1 = -2;

std::string smear_scene(float open, float close, int spp) {
  const double vfov = 2 * std::atan(kTanHalf) * 180 / std::numbers::pi;
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 0, 0], "look_at": [0, 0, 1], "vfov": {},
                "shutter": [{}, {}]}},
    "render": {{"resolution": [{}, {}], "spp": {}, "sampler": "independent", "seed": 3,
               "integrator": "raycast:mode=albedo"}},
    "materials": {{"white": {{"type": "diffuse", "albedo": 1}}}},
    "shapes": [{{"type": "sphere", "center": [0, {}, {}], "radius": {}, "material": "white",
                "transform": [{{"translate": [{}, 0, 0]}}],
                "transform_end": [{{"translate": [{}, 0, 0]}}]}}]}})",
                     vfov, open, close, kW, kH, spp, kY, kDepth, kRadius, kX0, kX1);
}

/// The exact coverage of pixel (px, py): the fraction of the pixel's area and of the shutter
/// [open, close] (within [0, 1]) in which the camera ray meets the sphere, integrated over the
/// pixel by a q x q midpoint rule. For a ray direction d the squared distance from the sphere's
/// centre c(t) = c0 + v t to the ray's line is quadratic in t; the times it is below r^2 form an
/// interval.
double exact_coverage(const PinholeCamera& cam, int px, int py, double open, double close, int q) {
  double sum = 0;
  for (int j = 0; j < q; ++j)
    for (int i = 0; i < q; ++i) {
      const Vec3 df = cam.generate_ray({{px + (i + 0.5f) / q, py + (j + 0.5f) / q}, {}, 0}).d;
      const double d[3] = {df.x, df.y, df.z};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double c0[3] = {kX0, kY, kDepth}, v[3] = {kX1 - kX0, 0, 0};
      double cd = 0, vd = 0, cc = 0, vv = 0, cv = 0;
      for (int a = 0; a < 3; ++a) {
        cd += c0[a] * d[a] / len, vd += v[a] * d[a] / len;
        cc += c0[a] * c0[a], vv += v[a] * v[a], cv += c0[a] * v[a];
      }
      const double A = vv - vd * vd, B = 2 * (cv - cd * vd), C = cc - cd * cd - kRadius * kRadius;
      const double disc = B * B - 4 * A * C;
      if (disc <= 0) continue;
      const double t0 = (-B - std::sqrt(disc)) / (2 * A), t1 = (-B + std::sqrt(disc)) / (2 * A);
      sum += std::max(0.0, std::min(t1, close) - std::max(t0, open)) / (close - open);
    }
  return sum / (q * q);
}

/// Checks the rendered smear for shutter [open, close] at `spp` samples per pixel.
void check_smear(float open, float close, int spp) {
  const RgbImage img = test::render_desc(test::scene_from_text(smear_scene(open, close, spp)));
  const PinholeCamera cam({0, 0, 0}, {0, 0, 1}, {0, 1, 0},
                          float(2 * std::atan(kTanHalf) * 180 / std::numbers::pi), kW, kH);
  // Per pixel: a sample is a Bernoulli(p) draw, so the pixel mean has standard deviation
  // sqrt(p (1 - p) / spp); allow five of them, plus 0.002 for the midpoint rule's error.
  double sum = 0, exact_sum = 0, variance = 0;
  std::vector<double> row(kW), exact_row(kW);
  int bad = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double p = exact_coverage(cam, x, y, open, close, 24);
      const double got = img.at(x, y).g;
      const double bound = 5 * std::sqrt(p * (1 - p) / spp) + 0.002;
      if (std::fabs(got - p) > bound && ++bad <= 5)
        ADD_FAILURE() << "pixel (" << x << ", " << y << "): coverage " << got << ", exact " << p
                      << " +- " << bound;
      sum += got, exact_sum += p, variance += p * (1 - p) / spp;
      if (y == kH / 2 - 1) row[size_t(x)] = got, exact_row[size_t(x)] = p;  // the centre's row
    }
  EXPECT_EQ(bad, 0);
  // Mean coverage: the image's total is the time-averaged area of the sphere's image, pi r^2
  // pixels (r = 5; the perspective adds under 0.1%).
  EXPECT_NEAR(sum, exact_sum, 5 * std::sqrt(variance) + 0.02);
  EXPECT_NEAR(exact_sum, std::numbers::pi * 25, 0.001 * std::numbers::pi * 25);
  // Smear length: the profile along the centre row is a trapezoid whose width at half its
  // plateau is the distance the centre travels while the shutter is open, 40 (close - open)
  // pixels. Measured between the rendered profile's crossings of half the exact plateau (linear
  // interpolation between pixels). A pixel's noise moves a crossing by about sigma / slope:
  // sqrt(p (1 - p) / 8192) / (1 / 40) = 0.15 pixel for the full shutter (p = 1/8), so the length
  // is known to about 0.2 pixel (measured: 39.80 and 19.78 pixels).
  const double plateau = *std::max_element(exact_row.begin(), exact_row.end());
  const double half = 0.5 * plateau;
  const auto crossing = [&](int from, int step) {
    for (int x = from; x + step >= 0 && x + step < kW; x += step)
      if (row[size_t(x)] < half && row[size_t(x + step)] >= half)
        return x + (half - row[size_t(x)]) / (row[size_t(x + step)] - row[size_t(x)]) * step;
    return -1.0;
  };
  const double length = crossing(kW - 1, -1) - crossing(0, 1);

  EXPECT_NEAR(length, 40.0 * (close - open), 1.0) << "shutter [" << open << ", " << close << "]";
  // The plateau: the chord 2 r over the travel, in the fraction of the shutter.
  EXPECT_NEAR(plateau, 2 * 5 / (40.0 * (close - open)), 0.01);
}

// A sphere of radius 5 pixels moving 40 pixels while the shutter is open: every pixel's coverage
// is the exact fraction of the shutter during which the sphere covers it, the smear is 40 pixels
// long and the image's total coverage is the sphere's area.
TEST(MotionBlur, MovingSphereLeavesTheExactSmear) {
  check_smear(0.0f, 1.0f, 8192);
}

// Half the shutter: half the smear, centred on the middle of the path.
TEST(MotionBlur, HalfTheShutterLeavesHalfTheSmear) {
  check_smear(0.25f, 0.75f, 8192);
}

// Motion-blurred renders stay bit-identical at any thread count, and every structure renders the
// bundled motion-blur scene bit-identically to brute force.
TEST(MotionBlur, RendersAreDeterministicAndEqualForEveryStructure) {
  auto desc = test::bundled_scene("motion-blur.json");
  desc.render.width = 48;
  desc.render.height = 32;
  desc.render.spp = 2;
  desc.render.accel = "brute";
  const RgbImage reference = test::render_desc(desc, 1);
  EXPECT_TRUE(test::render_desc(desc, 2) == reference);
  for (const AccelInfo& info : accelerator_list()) {
    desc.render.accel = info.name;
    EXPECT_TRUE(test::render_desc(desc) == reference) << info.name;
  }
}

// The world keeps moving shapes' motion; equal ends make static primitives; a moving emitter
// described programmatically is refused like the loader refuses it.
TEST(MotionBlur, WorldBuildsMovingAndStaticPrimitives) {
  const std::string base = R"({
    "camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},
    "materials": {"m": {"type": "diffuse"}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m",
                "transform_end": [{"translate": [1, 0, 0]}]},
               {"type": "quad", "origin": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
                "material": "m", "transform_end": [{"scale": 1}]}]})";
  SceneDesc desc = test::scene_from_text(base);
  const World world(desc, "bvh");
  EXPECT_TRUE(world.primitives().moving(0));
  EXPECT_FALSE(world.primitives().moving(1));  // its ends coincide
  EXPECT_EQ(world.primitives().sphere_end(0).center, Vec3(1, 0, 0));
  desc.shapes[0].emission = Rgb(1.0f);
  EXPECT_THROW(World(desc, "bvh"), InputError);
}

}  // namespace
}  // namespace penumbra
