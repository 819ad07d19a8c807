// The alias table and light selection: empirical frequencies against the pmf (chi-square), zero
// weights never picked, the reused remainder uniform, and the strategies' probabilities.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/light/directional_light.h"
#include "penumbra/render/light/light_sampler.h"
#include "penumbra/render/light/point_light.h"
#include "penumbra/render/sampling/alias_table.h"
#include "chi_square.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

using test::chi_square;

TEST(AliasTable, FrequenciesAndRemaindersFollowTheWeights) {
  const std::vector<float> weights = {0, 1, 2.5f, 0, 7, 0.5f, 3, 1e-3f, 0.25f};
  const AliasTable table(weights);
  double sum = 0;
  for (float w : weights) sum += w;
  ASSERT_EQ(table.size(), weights.size());
  for (uint32_t i = 0; i < table.size(); ++i) EXPECT_NEAR(table.pmf(i), weights[i] / sum, 1e-7);
  // Joint bins of (item, remainder): the remainder is uniform and independent of the choice.
  constexpr int kR = 10, n = 400000;
  std::vector<double> observed(weights.size() * kR, 0.0), expected(weights.size() * kR);
  for (size_t i = 0; i < weights.size(); ++i)
    for (int r = 0; r < kR; ++r) expected[i * kR + r] = n * weights[i] / sum / kR;
  Pcg32 rng(21);
  for (int k = 0; k < n; ++k) {
    float pmf, rest;
    const uint32_t i = table.sample(rng.next_float(), &pmf, &rest);
    ASSERT_LT(i, table.size());
    ASSERT_GT(weights[i], 0.0f) << "picked an item of weight zero";
    ASSERT_EQ(pmf, table.pmf(i));
    ASSERT_TRUE(rest >= 0.0f && rest < 1.0f);
    observed[i * kR + std::min(int(rest * kR), kR - 1)] += 1;
  }
  EXPECT_TRUE(chi_square(observed, expected));
}

TEST(AliasTable, DegenerateWeightsGiveAUniformTable) {
  const std::vector<float> zeros = {0, -1, std::nanf(""), 0};
  const AliasTable table(zeros);
  for (uint32_t i = 0; i < table.size(); ++i) EXPECT_FLOAT_EQ(table.pmf(i), 0.25f);
  // Same weights, same table: the same samples.
  const std::vector<float> w = {3, 1, 4, 1, 5, 9, 2, 6};
  const AliasTable a(w), b(w);
  for (float u = 0; u < 1.0f; u += 1.0f / 997) EXPECT_EQ(a.sample(u), b.sample(u));
}

/// Draws n lights from `sampler` and checks the frequencies against its pmf.
void expect_frequencies_match(const LightSampler& sampler, uint64_t seed) {
  const auto& lights = sampler.lights();
  const int n = 200000;
  std::vector<double> observed(lights.size(), 0.0), expected(lights.size());
  for (size_t i = 0; i < lights.size(); ++i) expected[i] = n * sampler.pmf(lights[i]);
  Pcg32 rng(seed);
  for (int k = 0; k < n; ++k) {
    const SampledLight s = sampler.sample(rng.next_float());
    ASSERT_NE(s.light, nullptr);
    ASSERT_GT(s.pmf, 0.0f);
    ASSERT_EQ(s.pmf, sampler.pmf(s.light));
    for (size_t i = 0; i < lights.size(); ++i)
      if (lights[i] == s.light) observed[i] += 1;
  }
  EXPECT_TRUE(chi_square(observed, expected));
}

TEST(LightSampler, PowerStrategyFollowsLuminanceOfPower) {
  PointLight a({0, 0, 0}, Rgb(1.0f)), b({1, 0, 0}, Rgb(0.0f)), c({0, 1, 0}, Rgb(5, 0, 0)),
      d({0, 0, 1}, Rgb(0, 0, 2));
  DirectionalLight e({0, -1, 0}, Rgb(0.5f));
  e.preprocess({{-1, -1, -1}, {1, 1, 1}});
  const std::vector<const Light*> lights = {&a, &b, &c, &d, &e};
  const LightSampler sampler(lights, "power");
  double sum = 0;
  for (const Light* l : lights) sum += l->power().luminance();
  for (const Light* l : lights) EXPECT_NEAR(sampler.pmf(l), l->power().luminance() / sum, 1e-6);
  EXPECT_EQ(sampler.pmf(&b), 0.0f);
  expect_frequencies_match(sampler, 22);
}

TEST(LightSampler, UniformStrategyIgnoresPower) {
  PointLight a({0, 0, 0}, Rgb(1.0f)), b({1, 0, 0}, Rgb(0.0f)), c({0, 1, 0}, Rgb(50.0f));
  const LightSampler sampler({&a, &b, &c}, "uniform");
  for (const Light* l : sampler.lights()) EXPECT_FLOAT_EQ(sampler.pmf(l), 1.0f / 3.0f);
  expect_frequencies_match(sampler, 23);
}

TEST(LightSampler, AllZeroPowerFallsBackToUniform) {
  PointLight a({0, 0, 0}, Rgb(0.0f)), b({1, 0, 0}, Rgb(0.0f));
  const LightSampler sampler({&a, &b}, "power");
  EXPECT_FLOAT_EQ(sampler.pmf(&a), 0.5f);
  EXPECT_FLOAT_EQ(sampler.pmf(&b), 0.5f);
}

TEST(LightSampler, EdgeCases) {
  PointLight a({0, 0, 0}, Rgb(1.0f)), outsider({0, 0, 0}, Rgb(1.0f));
  const LightSampler one({&a}, "power");
  EXPECT_EQ(one.pmf(&outsider), 0.0f);
  EXPECT_EQ(one.pmf(nullptr), 0.0f);
  EXPECT_EQ(one.sample(0.999999f).light, &a);
  const LightSampler none({}, "power");
  EXPECT_EQ(none.sample(0.5f).light, nullptr);
  try {
    const LightSampler bad({&a}, "bogus");
    FAIL() << "an unknown strategy was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("valid: power, uniform"), std::string::npos) << e.what();
  }
}

TEST(LightSampler, WorldLightsByPower) {
  // A point light, two area lights and the background: every light of the world, by power.
  const SceneDesc desc = test::scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},
    "render": {"background": [0.1, 0.1, 0.1]},
    "materials": {"b": {"type": "diffuse", "albedo": 0}},
    "lights": [{"type": "point", "position": [0, 3, 0], "intensity": 10}],
    "shapes": [
      {"type": "quad", "origin": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "b",
       "emission": [1, 2, 3]},
      {"type": "sphere", "center": [3, 0, 0], "radius": 0.5, "material": "b", "emission": 4}]})");
  const World world(desc, "bvh");
  ASSERT_EQ(world.lights().size(), 4u);
  const LightSampler sampler(world.lights(), "power");
  double sum = 0, total = 0;
  for (const Light* l : world.lights()) sum += l->power().luminance();
  for (const Light* l : world.lights()) {
    EXPECT_NEAR(sampler.pmf(l), l->power().luminance() / sum, 1e-6);
    total += sampler.pmf(l);
  }
  EXPECT_NEAR(total, 1.0, 1e-6);
  expect_frequencies_match(sampler, 24);
}

}  // namespace
}  // namespace penumbra
