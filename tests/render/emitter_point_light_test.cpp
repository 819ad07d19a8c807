#include <gtest/gtest.h>

#include <numbers>

#include "penumbra/core/rng.h"
#include "penumbra/render/light/emitter_point_light.h"
#include "penumbra/render/sampling.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

// The stand-in's intensity, integrated over the sphere of directions, equals the emitter's power
// (pi A L for a one-sided flat emitter, 4 pi^2 r^2 L for a sphere).
TEST(EmitterPointLight, RadiatesTheShapesPower) {
  const auto desc = test::scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},
    "materials": {"b": {"type": "diffuse", "albedo": 0}},
    "shapes": [
      {"type": "quad", "origin": [0, 0, 0], "edge1": [2, 0, 0], "edge2": [0, 3, 0], "material": "b",
       "emission": [1, 2, 3]},
      {"type": "sphere", "center": [10, 0, 0], "radius": 0.5, "material": "b", "emission": [1, 1, 1]}]})");
  const World world(desc, "brute");
  ASSERT_EQ(world.emitters().size(), 2u);
  const EmitterPointLight quad(world, world.emitters()[0]);
  const EmitterPointLight sphere(world, world.emitters()[1]);
  EXPECT_NEAR(quad.power().g, std::numbers::pi_v<float> * 6.0f * 2.0f, 1e-4f);
  // Monte Carlo integral of the intensity over directions: uniform sphere sampling, pdf 1/(4 pi).
  Pcg32 rng(11);
  const int n = 200000;
  double sum_quad = 0, sum_sphere = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 w = sample_uniform_sphere({rng.next_float(), rng.next_float()});
    sum_quad += quad.intensity(w).g;
    sum_sphere += sphere.intensity(w).r;
  }
  const double four_pi = 4.0 * std::numbers::pi;
  // I(w) = 12 max(0, w.z): mean 3, variance 144/6 - 9 = 15, so the mean's standard deviation is
  // sqrt(15 / n) ~ 0.0087; bound at 5 standard deviations (times 4 pi).
  EXPECT_NEAR(sum_quad / n * four_pi, quad.power().g, 5 * 0.0087 * four_pi);
  EXPECT_NEAR(sum_sphere / n * four_pi, sphere.power().r, 1e-3);
}

}  // namespace
}  // namespace penumbra
