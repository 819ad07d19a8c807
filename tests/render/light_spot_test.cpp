// The spot light: incident light inside the cone, in its falloff band and outside; emitted rays
// (all within the cone, distributed as pdf_le says, carrying the power); the power against
// Monte Carlo integration of the intensity; parameters; a render against the analytic radiance.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "chi_square.h"
#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/light/light_registry.h"
#include "penumbra/render/light/spot_light.h"
#include "penumbra/render/sampling.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

/// Parameters from JSON text, as the scene loader hands them to a light.
SceneParams params(const std::string& json) {
  return SceneParams(nlohmann::json::parse(json), "test.json", "/lights/0");
}

/// The message of the InputError that `make` throws (empty when it throws none).
template <class F>
std::string error_of(F make) {
  try {
    make();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// pbrt-v4's falloff in double precision: smoothstep(cos_end, cos_start, c).
double falloff(double c, double cone_deg, double delta_deg) {
  const double e = std::cos(cone_deg * kPi / 180), s = std::cos((cone_deg - delta_deg) * kPi / 180);
  const double t = std::fmin(1.0, std::fmax(0.0, (c - e) / (s - e)));
  return t * t * (3 - 2 * t);
}

/// The spot of most tests: at (1, 2, 3), aimed along -y, cone 30 degrees, falloff from 20.
SpotLight test_spot() {
  return SpotLight({1, 2, 3}, {0, -5, 0}, Rgb(2, 3, 4), 30.0f, 10.0f);
}

TEST(SpotLight, IncidentLightInsideInTheBandAndOutsideTheCone) {
  const SpotLight light = test_spot();
  EXPECT_TRUE(light.is_delta());
  EXPECT_EQ(light.axis(), Vec3(0, -1, 0));
  const Vec3 pos{1, 2, 3};
  // A receiver 2 below the light at angle a from the axis, in the x-y plane.
  const auto at = [&](double a_deg) {
    const double a = a_deg * kPi / 180;
    return pos + Vec3(float(2 * std::sin(a)), float(-2 * std::cos(a)), 0);
  };
  for (double a : {0.0, 10.0, 19.0, 22.0, 25.0, 29.0, 31.0, 60.0, 120.0, 180.0}) {
    const LightSample ls = light.sample_li(at(a), {0.3f, 0.6f});
    const double f = falloff(std::cos(a * kPi / 180), 30, 10);
    EXPECT_NEAR(ls.distance, 2.0, 1e-5);
    EXPECT_NEAR(ls.li.r, 2 * f / 4, 2e-5) << a << " degrees";
    EXPECT_NEAR(ls.li.b, 4 * f / 4, 2e-5) << a << " degrees";
    EXPECT_TRUE(ls.delta);
    EXPECT_EQ(ls.pdf, 1.0f);
    const Vec3 to_light = normalize(pos - at(a));
    EXPECT_NEAR(dot(ls.wi, to_light), 1.0, 1e-6);
  }
  // Full intensity within 20 degrees, none beyond 30, strictly between in the band.
  EXPECT_FLOAT_EQ(light.sample_li(at(15), {}).li.g, 0.75f);
  EXPECT_EQ(light.sample_li(at(30.5), {}).li.g, 0.0f);
  const float mid = light.sample_li(at(25), {}).li.g;
  EXPECT_GT(mid, 0.0f);
  EXPECT_LT(mid, 0.75f);
  EXPECT_EQ(light.sample_li(pos, {}).pdf, 0.0f);  // at the light: nothing
}

TEST(SpotLight, PowerIsTheIntensityOverTheFalloffSolidAngle) {
  const SpotLight light = test_spot();
  const double cs = std::cos(20 * kPi / 180), ce = std::cos(30 * kPi / 180);
  const double k = 2 * kPi * ((1 - cs) + (cs - ce) / 2);
  EXPECT_NEAR(light.power().r, 2 * k, 1e-5);
  EXPECT_NEAR(light.power().b, 4 * k, 1e-5);
  // Monte Carlo over uniform directions on the sphere: 4 pi E[I(w)], within 4 sigma.
  Pcg32 rng(71);
  const int n = 400000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 w = sample_uniform_sphere({rng.next_float(), rng.next_float()});
    const double v = 4 * kPi * light.intensity(w).g;
    sum += v, sum2 += v * v;
  }
  const double mean = sum / n, sigma = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_GT(sigma, 0.0);
  EXPECT_NEAR(mean, light.power().g, 4 * sigma);
  // A sharp cone (no band) and a cone that is all band.
  EXPECT_NEAR(SpotLight({}, {0, 0, 1}, Rgb(1), 60, 0).power().g, 2 * kPi * 0.5, 1e-5);
  EXPECT_NEAR(SpotLight({}, {0, 0, 1}, Rgb(1), 90, 90).power().g, 2 * kPi * 0.5, 1e-5);
}

TEST(SpotLight, EmittedRaysStayInTheConeAndFollowPdfLe) {
  const SpotLight light = test_spot();
  // Histogram of cos theta over [cos_end, 1]: bins by cos theta, expected counts from the
  // density pdf_le integrated over each bin (2 pi dcos, Simpson's rule).
  constexpr int kB = 24, n = 200000;
  const double ce = light.cos_end();
  std::vector<double> observed(kB, 0.0), expected(kB, 0.0);
  Pcg32 rng(72);
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const LightLeSample s = light.sample_le({rng.next_float(), rng.next_float()},
                                            {rng.next_float(), rng.next_float()}, 0.5f);
    ASSERT_EQ(s.ray.o, Vec3(1, 2, 3));
    ASSERT_NEAR(length(s.ray.d), 1.0f, 1e-5f);
    ASSERT_EQ(s.ray.time, 0.5f);
    const double c = dot(s.ray.d, light.axis());
    ASSERT_GE(c, ce - 1e-6) << "a ray outside the cone";
    float pdf_pos, pdf_dir;
    light.pdf_le(s.ray, s.n, pdf_pos, pdf_dir);
    ASSERT_EQ(pdf_pos, 0.0f);  // a delta in position
    ASSERT_NEAR(pdf_dir, s.pdf_dir, 1e-4f * s.pdf_dir);
    observed[std::min(int((c - ce) / (1 - ce) * kB), kB - 1)] += 1;
    const double b = s.beta().g;
    sum += b, sum2 += b * b;
  }
  for (int i = 0; i < kB; ++i) {
    const double a = ce + (1 - ce) * i / kB, h = (1 - ce) / kB;
    const auto pdf = [&](double c) {
      Ray r;
      r.d = light.axis() * float(c) + Vec3(1, 0, 0) * float(std::sqrt(1 - c * c));
      float pp, pd;
      light.pdf_le(r, {}, pp, pd);
      return double(pd);
    };
    double integral = 0;
    for (int j = 0; j < 16; ++j) {
      const double x0 = a + h * j / 16, x1 = a + h * (j + 1) / 16;
      integral += (x1 - x0) / 6 * (pdf(x0) + 4 * pdf(0.5 * (x0 + x1)) + pdf(x1));
    }
    expected[i] = n * 2 * kPi * integral;
  }
  EXPECT_TRUE(test::chi_square(observed, expected));
  // The Monte Carlo estimate of the power from the emitted rays, E[beta], within 4 sigma (plus
  // float rounding: the density is proportional to the intensity, so beta barely varies).
  const double mean = sum / n, sigma = std::sqrt(std::fmax(0.0, sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, light.power().g, 4 * sigma + 1e-5 * light.power().g);
}

TEST(SpotLight, SmoothstepSamplingInvertsItsIntegral) {
  for (int i = 0; i <= 1000; ++i) {
    const float u = i / 1000.0f, t = sample_smoothstep_unit(u);
    ASSERT_GE(t, 0.0f);
    ASSERT_LE(t, 1.0f);
    ASSERT_NEAR(t * t * t * (2 - t), u, 2e-6f) << u;
  }
  EXPECT_EQ(spot_smoothstep(0.5f, 1.0f, 1.0f), 0.0f);  // a step when a == b
  EXPECT_EQ(spot_smoothstep(1.0f, 1.0f, 1.0f), 1.0f);
}

TEST(SpotLight, ParametersAreChecked) {
  const SpotLight at(
      params(R"({"type": "spot", "position": [0, 1, 0], "look_at": [0, 1, 5], "cone_angle": 45})"));
  EXPECT_EQ(at.axis(), Vec3(0, 0, 1));
  EXPECT_NEAR(at.cos_end(), std::cos(kPi / 4), 1e-6);
  EXPECT_NEAR(at.cos_start(), std::cos(40 * kPi / 180), 1e-6);  // default delta 5
  const SpotLight dflt(
      params(R"({"type": "spot", "position": [0, 0, 0], "direction": [1, 0, 0]})"));
  EXPECT_NEAR(dflt.cos_end(), std::cos(kPi / 6), 1e-6);  // default cone 30
  EXPECT_EQ(dflt.intensity({1, 0, 0}), Rgb(1.0f));
  const auto err = [](const std::string& extra) {
    return error_of(
        [&] { SpotLight(params(R"({"type": "spot", "position": [0, 0, 0])" + extra + "}")); });
  };
  const std::string dir = R"(, "direction": [0, 0, 1])";
  EXPECT_NE(err(dir + R"(, "cone_angle": 0)").find("test.json:/lights/0/cone_angle: must be in"),
            std::string::npos);
  EXPECT_NE(err(dir + R"(, "cone_angle": 181)").find("/lights/0/cone_angle"), std::string::npos);
  EXPECT_NE(err(dir + R"(, "cone_delta": -1)").find("/lights/0/cone_delta: must be in"),
            std::string::npos);
  EXPECT_NE(err(dir + R"(, "cone_angle": 10, "cone_delta": 11)").find("/lights/0/cone_delta"),
            std::string::npos);
  EXPECT_NE(err("").find("/lights/0/direction: give exactly one"), std::string::npos);
  EXPECT_NE(err(dir + R"(, "look_at": [1, 1, 1])").find("exactly one"), std::string::npos);
  EXPECT_NE(err(R"(, "look_at": [0, 0, 0])").find("/lights/0/look_at"), std::string::npos);
  EXPECT_NE(err(R"(, "direction": [0, 0, 0])").find("/lights/0/direction: must be"),
            std::string::npos);
  EXPECT_NE(err(dir + R"(, "intensity": -1)").find("non-negative"), std::string::npos);
  EXPECT_NE(err(dir + R"(, "angle": 3)").find("/lights/0/angle: unknown key"), std::string::npos);
  EXPECT_THROW(SpotLight({}, {0, 0, 0}, Rgb(1), 30, 5), Error);
  EXPECT_THROW(SpotLight({}, {0, 0, 1}, Rgb(1), 30, 40), Error);
  // The registry knows it.
  const auto made =
      make_light(params(R"({"type": "spot", "position": [0, 0, 0], "direction": [0, 1, 0]})"));
  EXPECT_EQ(made->kind(), LightKind::kDeltaPosition);
}

/// The radiance that `whitted` renders at floor point (r, 0, 0) under a spot 4 above the origin
/// aimed down, seen from straight above with a tiny field of view.
float rendered_floor(float r) {
  const std::string x = std::to_string(r);
  const auto desc = test::scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [)" +
                                          x + R"(, 10, 0], "look_at": [)" + x +
                                          R"(, 0, 0], "up": [0, 0, 1], "vfov": 0.01},
    "render": {"resolution": [5, 5], "spp": 1, "integrator": "whitted"},
    "materials": {"grey": {"type": "diffuse", "albedo": 0.5}},
    "lights": [{"type": "spot", "position": [0, 4, 0], "look_at": [0, 0, 0], "intensity": 8,
                "cone_angle": 30, "cone_delta": 10}],
    "shapes": [{"type": "quad", "origin": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0],
                "material": "grey"}]})");
  return test::render_desc(desc).at(2, 2).g;
}

TEST(SpotLight, RenderedFloorMatchesTheAnalyticRadiance) {
  // L = (albedo / pi) I falloff(cos) cos / d^2 with cos = 4 / d.
  for (double a_deg : {0.0, 12.0, 25.0, 35.0}) {
    const double r = 4 * std::tan(a_deg * kPi / 180), d = std::sqrt(16 + r * r), c = 4 / d;
    const double expected = 0.5 / kPi * 8 * falloff(c, 30, 10) * c / (d * d);
    EXPECT_NEAR(rendered_floor(float(r)), expected, 5e-3 * 0.5 / kPi * 8 / 16)
        << a_deg << " degrees";
  }
}

}  // namespace
}  // namespace penumbra
