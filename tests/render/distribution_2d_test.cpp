#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "penumbra/core/rng.h"
#include "penumbra/render/sampling/distribution_1d.h"
#include "penumbra/render/sampling/distribution_2d.h"

namespace penumbra {
namespace {

/// Pearson's statistic of `observed` against `expected` counts; bins with expected 0 are skipped
/// (the callers check that they stay empty). Sets `dof` to the bins used minus one.
double chi_square(const std::vector<double>& observed, const std::vector<double>& expected,
                  int& dof) {
  double chi2 = 0;
  dof = -1;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] <= 0) continue;
    chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++dof;
  }
  return chi2;
}

/// A chi-square statistic of k degrees of freedom has mean k and variance 2k; a bound six
/// standard deviations above the mean fails a correct sampler with probability far below 1e-6.
double chi_square_bound(int dof) {
  return dof + 6.0 * std::sqrt(2.0 * dof);
}

/// A 12 x 7 test function: values from 0.2 to 3, one zero row, zero cells (including the first
/// and last cell of the grid and of some rows).
std::vector<float> test_function(int nx, int ny) {
  std::vector<float> f(nx * ny);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) f[y * nx + x] = 0.2f + float((x * 7 + y * 3) % 11) * 0.28f;
  for (int x = 0; x < nx; ++x) f[2 * nx + x] = 0;  // a zero row
  f[0] = f[nx * ny - 1] = f[3 * nx + 5] = f[4 * nx] = f[5 * nx + nx - 1] = 0;
  return f;
}

// Samples fall into cells and into 4 x 4 sub-cells of each cell with the probabilities of the
// function (so both the cell choice and the continuous offset inside a cell are right), never into
// a zero cell, and report the density pdf() gives.
TEST(Distribution2D, SamplesPassAChiSquareTestAgainstTheFunction) {
  constexpr int kNx = 12, kNy = 7, kSub = 4, kSamples = 400000;
  const std::vector<float> f = test_function(kNx, kNy);
  const Distribution2D d(f, kNx, kNy);
  double total = 0;
  for (float v : f) total += v;

  std::vector<double> observed(kNx * kNy * kSub * kSub, 0.0), expected(observed.size());
  for (int y = 0; y < kNy * kSub; ++y)
    for (int x = 0; x < kNx * kSub; ++x)
      expected[y * kNx * kSub + x] =
          kSamples * f[(y / kSub) * kNx + x / kSub] / total / (kSub * kSub);
  Pcg32 rng(7);
  int pdf_mismatches = 0;
  for (int i = 0; i < kSamples; ++i) {
    const Sample2D s = d.sample({rng.next_float(), rng.next_float()});
    ASSERT_TRUE(s.p.x >= 0 && s.p.x < 1 && s.p.y >= 0 && s.p.y < 1);
    ASSERT_EQ(s.pdf, d.cell_pdf(s.x, s.y));
    if (d.pdf(s.p) != s.pdf) ++pdf_mismatches;  // only on a cell boundary, by rounding
    const int sx = std::min(int(s.p.x * kNx * kSub), kNx * kSub - 1);
    const int sy = std::min(int(s.p.y * kNy * kSub), kNy * kSub - 1);
    observed[sy * kNx * kSub + sx] += 1;
  }
  EXPECT_LE(pdf_mismatches, kSamples / 100000);
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] == 0) {
      EXPECT_EQ(observed[i], 0) << "sample in a zero cell, sub-cell " << i;
    }
  }
  int dof = 0;
  const double chi2 = chi_square(observed, expected, dof);
  RecordProperty("chi2", std::to_string(chi2) + " dof " + std::to_string(dof));
  EXPECT_LT(chi2, chi_square_bound(dof));
}

// The density of each cell is the function over its integral, and integrates to one.
TEST(Distribution2D, PdfIsTheNormalisedFunction) {
  constexpr int kNx = 12, kNy = 7;
  const std::vector<float> f = test_function(kNx, kNy);
  const Distribution2D d(f, kNx, kNy);
  double total = 0, sum = 0;
  for (float v : f) total += v;
  EXPECT_NEAR(d.integral(), total / (kNx * kNy), 1e-6 * total);
  for (int y = 0; y < kNy; ++y)
    for (int x = 0; x < kNx; ++x) {
      const float expected = static_cast<float>(f[y * kNx + x] / (total / (kNx * kNy)));
      EXPECT_NEAR(d.cell_pdf(x, y), expected, 1e-5f * expected) << x << ", " << y;
      EXPECT_EQ(d.pdf({(x + 0.5f) / kNx, (y + 0.5f) / kNy}), d.cell_pdf(x, y));
      sum += d.cell_pdf(x, y) / (kNx * kNy);
    }
  EXPECT_NEAR(sum, 1.0, 1e-5);
}

// A function that is zero everywhere gives the uniform density, and its samples are uniform.
TEST(Distribution2D, AllZeroFunctionIsUniform) {
  constexpr int kNx = 5, kNy = 3, kSamples = 100000;
  const Distribution2D d(std::vector<float>(kNx * kNy, 0.0f), kNx, kNy);
  EXPECT_EQ(d.integral(), 0.0);
  std::vector<double> observed(kNx * kNy, 0.0), expected(kNx * kNy, double(kSamples) / (kNx * kNy));
  Pcg32 rng(3);
  for (int i = 0; i < kSamples; ++i) {
    const Sample2D s = d.sample({rng.next_float(), rng.next_float()});
    EXPECT_NEAR(s.pdf, 1.0f, 1e-6f);
    observed[s.y * kNx + s.x] += 1;
  }
  int dof = 0;
  const double chi2 = chi_square(observed, expected, dof);
  EXPECT_LT(chi2, chi_square_bound(dof));
  EXPECT_NEAR(d.pdf({0.3f, 0.9f}), 1.0f, 1e-6f);
}

// Extreme uniforms land in cells of positive density even when the first and last cells are
// zero; sampling is deterministic; an empty function is one uniform cell.
TEST(Distribution2D, OneDimensionalEdgeCases) {
  const std::vector<float> f = {0, 0, 2, 0, 1, 0};
  const Distribution1D d(f);
  for (float u : {0.0f, 1e-7f, 0.5f, 0.66f, 0x1.fffffep-1f, 1.0f, -1.0f}) {
    const Sample1D s = d.sample(u);
    EXPECT_TRUE(s.cell == 2 || s.cell == 4) << u;
    EXPECT_GT(s.pdf, 0.0f);
    EXPECT_TRUE(s.x >= 0.0f && s.x < 1.0f);
    EXPECT_EQ(s.x, Distribution1D(f).sample(u).x);
  }
  EXPECT_NEAR(d.cell_pdf(2), 4.0f, 1e-6f);  // 2 / (3 / 6)
  EXPECT_NEAR(d.cell_pdf(4), 2.0f, 1e-6f);
  EXPECT_EQ(d.pdf(0.1f), 0.0f);
  const Distribution1D empty;
  EXPECT_EQ(empty.size(), 1);
  EXPECT_EQ(empty.sample(0.25f).x, 0.25f);
  EXPECT_EQ(empty.pdf(0.7f), 1.0f);
}

// The conditional sample inside a cell is uniform: x is linear in u within a cell.
TEST(Distribution2D, OneDimensionalSampleInvertsTheCdf) {
  const std::vector<float> f = {1, 3};
  const Distribution1D d(f);
  EXPECT_NEAR(d.sample(0.125f).x, 0.25f, 1e-6f);  // cdf(x) = x / 2 on the first half
  EXPECT_NEAR(d.sample(0.625f).x, 0.75f, 1e-6f);  // 0.25 + 1.5 (x - 0.5) on the second
  EXPECT_NEAR(d.sample(0.625f).pdf, 1.5f, 1e-6f);
}

}  // namespace
}  // namespace penumbra
