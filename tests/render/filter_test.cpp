#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/filter/filter.h"
#include "penumbra/render/filter/filter_sampler.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

TEST(FilterSampler, BoxIsUniformOverThePixelWithUnitWeight) {
  const auto box = make_filter("box");
  const FilterSampler fs(*box);
  Pcg32 rng(1);
  for (int i = 0; i < 10000; ++i) {
    const FilterSample s = fs.sample({rng.next_float(), rng.next_float()});
    EXPECT_GE(s.offset.x, -0.5f);
    EXPECT_LT(s.offset.x, 0.5f);
    EXPECT_EQ(s.weight, 1.0f);
  }
}

// Chi-square test of the sampled tent offsets against the tent density (1 - |x|) on [-1, 1]:
// 20 bins, 100,000 samples; the 0.999 quantile of chi-square with 19 degrees of freedom is 43.8.
TEST(FilterSampler, TentOffsetsFollowTheTentDensity) {
  const auto tent = make_filter("tent");
  const FilterSampler fs(*tent);
  Pcg32 rng(2);
  const int bins = 20, n = 100000;
  std::vector<int> count(bins, 0);
  for (int i = 0; i < n; ++i) {
    const FilterSample s = fs.sample({rng.next_float(), rng.next_float()});
    ++count[std::min(bins - 1, int((s.offset.x + 1.0f) / 2.0f * bins))];
    EXPECT_GT(s.weight, 0.0f);
  }
  double chi2 = 0;
  for (int b = 0; b < bins; ++b) {
    const double x0 = -1.0 + 2.0 * b / bins, x1 = x0 + 2.0 / bins;
    // Integral of (1 - |x|) over [x0, x1].
    auto cdf = [](double x) {
      return x < 0 ? 0.5 * (1 + x) * (1 + x) : 1 - 0.5 * (1 - x) * (1 - x);
    };
    const double expected = n * (cdf(x1) - cdf(x0));
    chi2 += (count[size_t(b)] - expected) * (count[size_t(b)] - expected) / expected;
  }
  EXPECT_LT(chi2, 43.8);
}

// Mitchell-Netravali has negative lobes: samples there carry negative weights, and the weighted
// estimate of the filtered value of a function matches the quadrature of f g / integral f.
TEST(FilterSampler, MitchellNegativeLobesGetNegativeWeights) {
  const auto mitchell = make_filter("mitchell");
  const FilterSampler fs(*mitchell);
  Pcg32 rng(3);
  double num = 0, den = 0;
  int negative = 0;
  const int n = 400000;
  auto g = [](double x) { return 1.0 + 0.3 * x * x; };  // an even test function
  for (int i = 0; i < n; ++i) {
    const FilterSample s = fs.sample({rng.next_float(), 0.5f});
    if (s.weight < 0) ++negative;
    num += s.weight * g(s.offset.x);
    den += s.weight;
  }
  EXPECT_GT(negative, n / 100);
  // Quadrature of the same filter (1D profile) with the midpoint rule.
  double qn = 0, qd = 0;
  for (int i = 0; i < 100000; ++i) {
    const double x = -2.0 + 4.0 * (i + 0.5) / 100000;
    const double f = mitchell->eval(float(x));
    qn += f * g(x), qd += f;
  }
  // Weights are +-constant, so the estimate is a ratio of two binomial-like sums; 5 standard
  // errors of the ratio here are below 0.01.
  EXPECT_NEAR(num / den, qn / qd, 0.01);
}

TEST(Filter, UnknownNamesAndBadParametersAreErrors) {
  EXPECT_THROW(make_filter("lanczos"), Error);
  EXPECT_THROW(make_filter("gaussian:sigma=-1"), Error);
  EXPECT_THROW(make_filter("box:width=2"), Error);
  EXPECT_NO_THROW(make_filter("mitchell:b=0,c=0.5,radius=2"));
}

// A scene of uniform radiance renders exactly that radiance with every filter and sampler,
// negative lobes included (the film divides by the sum of signed weights).
TEST(Filter, UniformRadianceIsReproducedByEveryFilter) {
  for (const FilterInfo& f : filter_list())
    for (const char* sampler : {"independent", "jittered", "sobol"}) {
      auto desc = test::scene_from_text(R"({
        "camera": {"type": "pinhole", "position": [0, 0, 0], "look_at": [0, 0, 1], "vfov": 10},
        "render": {"resolution": [8, 8], "spp": 16, "integrator": "raycast:mode=albedo",
                   "background": [0.25, 0.5, 2.0]},
        "shapes": []})");
      desc.render.filter = f.name;
      desc.render.sampler = sampler;
      const RgbImage img = test::render_desc(desc);
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
          EXPECT_NEAR(img.at(x, y).r, 0.25f, 1e-5f) << f.name << " " << sampler;
          EXPECT_NEAR(img.at(x, y).b, 2.0f, 1e-5f) << f.name << " " << sampler;
        }
    }
}

}  // namespace
}  // namespace penumbra
