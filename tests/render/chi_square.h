#pragma once
// Statistical helpers shared by the render tests.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace penumbra::test {

/// Pearson's chi-square of observed against expected counts; cells expecting fewer than 5 are
/// pooled into one (as pbrt-v4's chi-square tests). Passes below the upper 1e-4 quantile of the
/// chi-square distribution (Wilson-Hilferty approximation).
inline testing::AssertionResult chi_square(const std::vector<double>& observed,
                                           const std::vector<double>& expected) {
  double stat = 0, pool_o = 0, pool_e = 0;
  int cells = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < 5.0) {
      pool_o += observed[i], pool_e += std::fmax(expected[i], 0.0);
      continue;
    }
    stat += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++cells;
  }
  if (pool_e > 0.0)
    stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e, ++cells;
  else if (pool_o > 0.0)
    return testing::AssertionFailure() << pool_o << " samples where none are expected";
  const double k = cells - 1, z = 3.719;  // z: the standard normal's upper 1e-4 quantile
  const double limit = k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3.0);
  if (cells > 1 && stat <= limit) return testing::AssertionSuccess();
  return testing::AssertionFailure()
         << "chi-square " << stat << " over " << k << " degrees of freedom, limit " << limit;
}

}  // namespace penumbra::test
