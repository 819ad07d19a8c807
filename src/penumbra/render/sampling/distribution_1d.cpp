#include "penumbra/render/sampling/distribution_1d.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
}  // namespace

Distribution1D::Distribution1D(std::span<const float> f) {
  const size_t n = std::max<size_t>(f.size(), 1);
  cdf_.assign(n + 1, 0.0f);
  // Running sums in double, so that many small cells after large ones are not lost.
  std::vector<double> partial(n + 1, 0.0);
  for (size_t i = 0; i < f.size(); ++i) {
    const double v = f[i] > 0.0f && std::isfinite(f[i]) ? double(f[i]) : 0.0;
    partial[i + 1] = partial[i] + v;
  }
  const double total = partial[n];
  if (!(total > 0.0) || !std::isfinite(total)) {
    // Nothing to be proportional to: uniform.
    for (size_t i = 0; i <= n; ++i) cdf_[i] = static_cast<float>(double(i) / double(n));
    integral_ = 0.0;
  } else {
    // Normalised CDF; rounding is monotone, so zero cells keep zero width.
    for (size_t i = 0; i <= n; ++i) cdf_[i] = static_cast<float>(partial[i] / total);
    integral_ = total / double(n);
  }
  cdf_[n] = 1.0f;
}

int Distribution1D::cell_of(float x) const {
  const int n = size();
  const float s = x * static_cast<float>(n);
  if (!(s > 0.0f)) return 0;  // also NaN
  return std::min(static_cast<int>(s), n - 1);
}

Sample1D Distribution1D::sample(float u) const {
  u = std::clamp(u, 0.0f, kOneMinusEpsilon);
  // The last cell whose CDF start is <= u: then cdf_[i] <= u < cdf_[i + 1], so the cell has a
  // positive width (cdf_[n] = 1 > u keeps i < n).
  const int n = size();
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const int i = std::clamp(static_cast<int>(it - cdf_.begin()) - 1, 0, n - 1);
  const float width = cdf_[i + 1] - cdf_[i];
  const float du = width > 0.0f ? std::clamp((u - cdf_[i]) / width, 0.0f, kOneMinusEpsilon) : 0.0f;
  Sample1D s;
  s.cell = i;
  s.x = std::min((static_cast<float>(i) + du) / static_cast<float>(n), kOneMinusEpsilon);
  s.pdf = width * static_cast<float>(n);
  return s;
}

}  // namespace penumbra
