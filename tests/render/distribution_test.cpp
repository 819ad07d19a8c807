#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "render_helpers.h"

namespace penumbra {
namespace {

/// Irradiance at p (normal n) from a uniform Lambertian polygon of radiance L (vertices in order):
/// E = L/2 |sum_i theta_i (n . Gamma_i)|, theta_i the angle the edge (v_i, v_i+1) subtends at p
/// and Gamma_i the unit normal of the plane through p and the edge (Lambert's formula; see Arvo
/// 1995, "Applications of Irradiance Tensors to the Simulation of Non-Lambertian Phenomena").
double polygon_irradiance(const std::vector<Vec3>& poly, Vec3 p, Vec3 n, double radiance) {
  double sum = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3 a = normalize(poly[i] - p), b = normalize(poly[(i + 1) % poly.size()] - p);
    const double theta = std::acos(std::clamp(double(dot(a, b)), -1.0, 1.0));
    sum += theta * dot(normalize(cross(a, b)), n);
  }
  return radiance * 0.5 * std::fabs(sum);
}

/// Scene: a white diffuse floor (albedo 1) at y = 0, a downward-facing rectangular light of
/// radiance 1 at y = 1 over [x0, x1] x [z0, z1], an optional black blocker, and a camera with a
/// tiny field of view looking at the floor point p from the side. The centre pixel then shows
/// the floor's radiance E / pi.
std::string scene_json(Vec3 p, float x0, float x1, float z0, float z1, const std::string& extra) {
  auto v = [](Vec3 a) { return fmt::format("[{},{},{}]", a.x, a.y, a.z); };
  return R"({
    "camera": {"type": "pinhole", "position": )" +
         v(p + Vec3{2, 0.5f, 0.3f}) + R"(, "look_at": )" + v(p) + R"(, "vfov": 0.02},
    "render": {"resolution": [3, 3], "spp": 256, "sampler": "jittered",
               "integrator": "distribution:light_samples=16"},
    "materials": {"white": {"type": "diffuse", "albedo": 1}, "black": {"type": "diffuse", "albedo": 0}},
    "shapes": [
      {"type": "quad", "origin": [-10, 0, -10], "edge1": [0, 0, 20], "edge2": [20, 0, 0], "material": "white"},
      {"type": "quad", "origin": )" +
         v({x0, 1, z0}) + R"(, "edge1": )" + v({x1 - x0, 0, 0}) + R"(, "edge2": )" +
         v({0, 0, z1 - z0}) + R"(, "material": "black", "emission": 1})" + extra + "]}";
}

// The distribution integrator's soft-shadow estimate converges to the analytic irradiance under
// a rectangular light. 256 jittered pixel samples x 16 jittered light samples: the estimate's
// relative standard deviation is well below 0.2%, so 1% is a bound of over five deviations.
TEST(Distribution, IrradianceUnderARectangleMatchesTheFormFactor) {
  const Vec3 p{0.3f, 0, -0.2f};
  const auto desc = test::scene_from_text(scene_json(p, -0.5f, 1.0f, -0.4f, 0.6f, ""));
  const double e = polygon_irradiance(
      {{-0.5f, 1, -0.4f}, {1.0f, 1, -0.4f}, {1.0f, 1, 0.6f}, {-0.5f, 1, 0.6f}}, p, {0, 1, 0}, 1.0);
  const Rgb c = test::render_desc(desc).at(1, 1);
  RecordProperty("relative_error", std::to_string(c.g / (e / std::numbers::pi) - 1.0));
  EXPECT_NEAR(c.g, e / std::numbers::pi, 0.01 * e / std::numbers::pi);
}

// A blocker whose edge lies in the plane x = 0 through the receiving point hides exactly the half
// x > 0 of a light centred above it: the point gets half the irradiance.
TEST(Distribution, HalfOccludedLightGivesHalfTheIrradiance) {
  const Vec3 p{0, 0, 0};
  const std::string blocker = R"(,
      {"type": "quad", "origin": [0, 0.5, -2], "edge1": [0, 0, 4], "edge2": [2, 0, 0], "material": "black"})";
  const Rgb open =
      test::render_desc(test::scene_from_text(scene_json(p, -0.5f, 0.5f, -0.5f, 0.5f, "")))
          .at(1, 1);
  const Rgb half =
      test::render_desc(test::scene_from_text(scene_json(p, -0.5f, 0.5f, -0.5f, 0.5f, blocker)))
          .at(1, 1);
  const double e = polygon_irradiance(
      {{-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0.5f, 1, 0.5f}, {-0.5f, 1, 0.5f}}, p, {0, 1, 0}, 1.0);
  EXPECT_NEAR(open.g, e / std::numbers::pi, 0.01 * e / std::numbers::pi);
  RecordProperty("half_ratio", std::to_string(half.g / open.g));
  EXPECT_NEAR(half.g / open.g, 0.5, 0.01);
}

// Seen in a mirror, an area light keeps its radiance; seen directly, too.
TEST(Distribution, EmittersAreSeenDirectlyAndThroughMirrors) {
  const auto desc = test::scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [0, 0, 0], "look_at": [0, 0, 1], "vfov": 1},
    "render": {"resolution": [3, 3], "spp": 4, "integrator": "distribution", "max_depth": 2},
    "materials": {"m": {"type": "mirror", "reflectance": 0.5}, "black": {"type": "diffuse", "albedo": 0}},
    "shapes": [
      {"type": "quad", "origin": [-1, -1, 5], "edge1": [2, 0, 0], "edge2": [0, 2, 0], "material": "m"},
      {"type": "quad", "origin": [-1, -1, -1], "edge1": [2, 0, 0], "edge2": [0, 2, 0],
       "material": "black", "emission": [2, 4, 6]}]})");
  const Rgb c = test::render_desc(desc).at(1, 1);
  EXPECT_NEAR(c.r, 1.0f, 1e-5f);
  EXPECT_NEAR(c.b, 3.0f, 1e-5f);
}

TEST(Distribution, DeterministicAcrossThreadCounts) {
  auto desc = test::bundled_scene("cornell-box.json");
  desc.render.integrator = "distribution:light_samples=2";
  desc.render.width = desc.render.height = 48;
  desc.render.spp = 2;
  EXPECT_TRUE(test::render_desc(desc, 1) == test::render_desc(desc, 2));
}

}  // namespace
}  // namespace penumbra
