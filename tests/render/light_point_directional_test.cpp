// Point and directional lights: incident light, parameters, emitted rays (sample_le, pdf_le), and
// their power: E[beta] and the flux they deliver onto a receiving quad.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/light/directional_light.h"
#include "penumbra/render/light/light_registry.h"
#include "penumbra/render/light/point_light.h"
#include "penumbra/render/sampling.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

/// Pearson's chi-square of observed against expected counts (all expecting at least 5 here);
/// passes below the upper 1e-4 quantile (Wilson-Hilferty approximation).
testing::AssertionResult chi_square(const std::vector<double>& observed,
                                    const std::vector<double>& expected) {
  double stat = 0;
  for (size_t i = 0; i < observed.size(); ++i)
    stat += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
  const double k = double(observed.size()) - 1.0, z = 3.719;
  const double limit = k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3.0);
  if (stat <= limit) return testing::AssertionSuccess();
  return testing::AssertionFailure()
         << "chi-square " << stat << " over " << k << " degrees of freedom, limit " << limit;
}

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

/// One receiving quad (black, primitive 0), a sphere widening the bounds, a directional light.
const char* kReceiverScene = R"({
  "camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},
  "materials": {"b": {"type": "diffuse", "albedo": 0}},
  "lights": [{"type": "directional", "direction": [0.3, -1, 0.2], "irradiance": [2, 3, 4]}],
  "shapes": [
    {"type": "quad", "origin": [-0.5, 0, -0.4], "edge1": [1, 0.3, 0], "edge2": [0, 0, 0.8],
     "material": "b"},
    {"type": "sphere", "center": [3, 2, -1], "radius": 0.5, "material": "b"}]})";

/// Flux onto the world's quad (primitive 0) from n emitted rays of `light`: power times the
/// fraction of rays that hit it, and the standard deviation of that estimate (binomial).
void flux_onto_quad(const World& world, const Light& light, uint64_t seed, double& flux,
                    double& sigma) {
  Pcg32 rng(seed);
  const int n = 200000;
  int hits = 0, beta_mismatches = 0;
  RayCounter counter;
  for (int k = 0; k < n; ++k) {
    const LightLeSample s = light.sample_le({rng.next_float(), rng.next_float()},
                                            {rng.next_float(), rng.next_float()}, 0.0f);
    // E[beta] = power, here exactly: every emitted ray carries the same power.
    if (std::fabs(s.beta().g - light.power().g) > 1e-4f * light.power().g) ++beta_mismatches;
    SurfaceInteraction si;
    if (world.intersect(s.ray, si, counter) && si.prim == 0) ++hits;
  }
  EXPECT_EQ(beta_mismatches, 0) << "rays whose beta is not the power";
  const double f = double(hits) / n;
  flux = light.power().g * f;
  sigma = light.power().g * std::sqrt(f * (1.0 - f) / n);
}

TEST(PointLight, IncidentLightFallsOffWithDistanceSquared) {
  const PointLight light({1, 2, 3}, Rgb(4, 8, 12));
  const LightSample ls = light.sample_li({1, 2, 1}, {0.3f, 0.7f});
  EXPECT_EQ(ls.wi, Vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(ls.distance, 2.0f);
  EXPECT_EQ(ls.li, Rgb(1, 2, 3));
  EXPECT_TRUE(ls.delta);
  EXPECT_EQ(ls.pdf, 1.0f);
  EXPECT_EQ(light.sample_li({1, 2, 3}, {0.5f, 0.5f}).pdf, 0.0f);  // at the light: nothing
  EXPECT_EQ(light.power(), Rgb(4, 8, 12) * float(4.0 * kPi));
}

TEST(PointLight, EmitsUniformlyAndDeliversIntensityTimesSolidAngle) {
  const SceneDesc desc = test::scene_from_text(kReceiverScene);
  const World world(desc, "bvh");
  const PointLight light({0.1f, 1.5f, 0.2f}, Rgb(3.0f));
  // Directions uniform on the sphere: bins of (z, phi) of equal solid angle.
  constexpr int kB = 12, n = 200000;
  std::vector<double> observed(kB * kB, 0.0);
  Pcg32 rng(31);
  for (int k = 0; k < n; ++k) {
    const LightLeSample s = light.sample_le({rng.next_float(), rng.next_float()},
                                            {rng.next_float(), rng.next_float()}, 0.0f);
    const double phi = std::atan2(s.ray.d.y, s.ray.d.x) + kPi;
    observed[std::min(int((s.ray.d.z + 1.0f) * 0.5f * kB), kB - 1) * kB +
             std::min(int(phi / (2.0 * kPi) * kB), kB - 1)] += 1;
    float pdf_pos, pdf_dir;
    light.pdf_le(s.ray, s.n, pdf_pos, pdf_dir);
    ASSERT_EQ(pdf_pos, 0.0f);  // a delta in position
    ASSERT_FLOAT_EQ(pdf_dir, s.pdf_dir);
  }
  EXPECT_TRUE(chi_square(observed, std::vector<double>(kB * kB, double(n) / (kB * kB))));
  // Flux onto the quad = I times its solid angle (Van Oosterom, Strackee 1983, two triangles).
  const auto tri = [](Vec3 a, Vec3 b, Vec3 c) {
    const double la = length(a), lb = length(b), lc = length(c);
    return 2.0 * std::atan2(std::fabs(double(dot(a, cross(b, c)))),
                            la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la);
  };
  const Vec3 o = Vec3{-0.5f, 0, -0.4f} - Vec3{0.1f, 1.5f, 0.2f}, e1{1, 0.3f, 0}, e2{0, 0, 0.8f};
  const double omega = tri(o, o + e1, o + e1 + e2) + tri(o, o + e1 + e2, o + e2);
  double flux, sigma;
  flux_onto_quad(world, light, 32, flux, sigma);
  EXPECT_NEAR(flux, 3.0 * omega, 4.0 * sigma);
}

TEST(PointLight, ParametersAreChecked) {
  EXPECT_NE(
      error_of([] { PointLight(params(R"({"type": "point", "intensity": 1})")); }).find("position"),
      std::string::npos);
  EXPECT_NE(error_of([] {
              PointLight(params(R"({"type": "point", "position": [0, 0, 0], "intensity": -1})"));
            }).find("non-negative"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              PointLight(params(R"({"type": "point", "position": [0, 0, 0], "colour": 1})"));
            }).find("colour"),
            std::string::npos);
}

TEST(DirectionalLight, ParametersAreChecked) {
  const DirectionalLight light(params(R"({"type": "directional", "direction": [0, -2, 0]})"));
  EXPECT_EQ(light.direction(), Vec3(0, -1, 0));
  EXPECT_EQ(light.sample_li({}, {}).li, Rgb(1.0f));  // default irradiance
  const std::string zero = error_of(
      [] { DirectionalLight(params(R"({"type": "directional", "direction": [0, 0, 0]})")); });
  EXPECT_NE(zero.find("test.json:/lights/0/direction"), std::string::npos) << zero;
  EXPECT_NE(
      error_of([] { DirectionalLight(params(R"({"type": "directional"})")); }).find("direction"),
      std::string::npos);
  EXPECT_NE(error_of([] {
              DirectionalLight(params(
                  R"({"type": "directional", "direction": [0, 0, 1], "irradiance": [1, -1, 1]})"));
            }).find("non-negative"),
            std::string::npos);
  EXPECT_NE(
      error_of([] {
        DirectionalLight(params(R"({"type": "directional", "direction": [0, 0, 1], "to": 1})"));
      }).find("/lights/0/to: unknown key"),
      std::string::npos);
  // The registry knows it.
  const auto made = make_light(params(R"({"type": "directional", "direction": [1, 0, 0]})"));
  EXPECT_EQ(made->kind(), LightKind::kDeltaDirection);
}

TEST(DirectionalLight, IncidentLightIsADeltaAgainstTheDirection) {
  const DirectionalLight light({0, 0, -3}, Rgb(1, 2, 3));
  const LightSample ls = light.sample_li({5, 6, 7}, {0.2f, 0.9f});
  EXPECT_EQ(ls.wi, Vec3(0, 0, 1));
  EXPECT_TRUE(std::isinf(ls.distance));
  EXPECT_EQ(ls.li, Rgb(1, 2, 3));
  EXPECT_EQ(ls.pdf, 1.0f);
  EXPECT_TRUE(ls.delta);
  EXPECT_EQ(light.pdf_li({}, {0, 0, 1}, {}), 0.0f);
  EXPECT_TRUE(light.is_delta());
}

TEST(DirectionalLight, EmitsFromADiscOutsideTheSceneAndDeliversIrradianceTimesArea) {
  const SceneDesc desc = test::scene_from_text(kReceiverScene);
  const World world(desc, "bvh");
  ASSERT_EQ(world.lights().size(), 1u);
  const auto& light = dynamic_cast<const DirectionalLight&>(*world.lights()[0]);
  Vec3 center;
  float r;
  bounding_sphere(world.bounds(), center, r);
  EXPECT_NEAR(light.power().g, 3.0 * kPi * r * r, 1e-4 * light.power().g);
  // Origins uniform on the disc: bins of (rho^2, phi) of equal area; all behind the scene.
  const Vec3 d = light.direction();
  Vec3 t, b;
  orthonormal_basis(d, t, b);
  constexpr int kB = 10, n = 100000;
  std::vector<double> observed(kB * kB, 0.0);
  Pcg32 rng(33);
  for (int k = 0; k < n; ++k) {
    const LightLeSample s = light.sample_le({rng.next_float(), rng.next_float()},
                                            {rng.next_float(), rng.next_float()}, 0.0f);
    ASSERT_EQ(s.ray.d, d);
    const Vec3 v = s.ray.o - center;
    ASSERT_NEAR(dot(v, d), -r, 1e-4f * r);
    const double x = dot(v, t) / r, y = dot(v, b) / r, rho2 = x * x + y * y;
    ASSERT_LE(rho2, 1.0 + 1e-5);
    const double phi = std::atan2(y, x) + kPi;
    observed[std::min(int(rho2 * kB), kB - 1) * kB + std::min(int(phi / (2 * kPi) * kB), kB - 1)] +=
        1;
    float pdf_pos, pdf_dir;
    light.pdf_le(s.ray, s.n, pdf_pos, pdf_dir);
    ASSERT_FLOAT_EQ(pdf_pos, s.pdf_pos);
    ASSERT_FLOAT_EQ(s.pdf_pos, float(1.0 / (kPi * r * r)));
    ASSERT_EQ(pdf_dir, 0.0f);  // a delta in direction
  }
  EXPECT_TRUE(chi_square(observed, std::vector<double>(kB * kB, double(n) / (kB * kB))));
  // Flux onto the quad = E |cos| A, cos between the light's direction and the quad's normal.
  const Vec3 area_normal = cross(Vec3{1, 0.3f, 0}, Vec3{0, 0, 0.8f});
  double flux, sigma;
  flux_onto_quad(world, light, 34, flux, sigma);
  EXPECT_NEAR(flux, 3.0 * std::fabs(dot(area_normal, d)), 4.0 * sigma);
}

}  // namespace
}  // namespace penumbra
