#include "penumbra/render/filter/filter_sampler.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

FilterSampler::FilterSampler(const Filter& filter, int resolution) : radius_(filter.radius()) {
  box_ = filter.name().rfind("box", 0) == 0;
  const int n = std::max(2, resolution);
  f_.resize(size_t(n) + 1);
  abs_.resize(size_t(n) + 1);
  cdf_.assign(size_t(n) + 1, 0.0f);
  const double dx = 2.0 * radius_ / n;
  for (int i = 0; i <= n; ++i) {
    // Nodes just inside the support at both ends, where filters reach zero.
    const double x = std::clamp(-radius_ + dx * i, -radius_ * 0.999999, radius_ * 0.999999);
    f_[size_t(i)] = filter.eval(float(x));
    abs_[size_t(i)] = std::fabs(f_[size_t(i)]);
  }
  // Trapezoid rule: the exact integral of the piecewise-linear density.
  double sum = 0;
  for (int i = 1; i <= n; ++i) {
    sum += 0.5 * (abs_[size_t(i - 1)] + abs_[size_t(i)]) * dx;
    cdf_[size_t(i)] = float(sum);
  }
  integral_ = float(sum);
  for (float& c : cdf_) c = integral_ > 0 ? c / integral_ : 0.0f;
}

float FilterSampler::pdf_1d(float x) const {
  if (!(std::fabs(x) < radius_)) return 0.0f;
  if (box_) return 0.5f / radius_;
  const int n = int(abs_.size()) - 1;
  const float s = (x + radius_) / (2 * radius_) * float(n);
  const int i = std::clamp(int(s), 0, n - 1);
  const float t = s - float(i);
  return ((1 - t) * abs_[size_t(i)] + t * abs_[size_t(i) + 1]) / integral_;
}

float FilterSampler::sample_1d(float u, float& pdf) const {
  if (box_) {
    pdf = 0.5f / radius_;
    return (2.0f * u - 1.0f) * radius_;
  }
  const int n = int(abs_.size()) - 1;
  // The segment whose CDF range holds u.
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const int i = std::clamp(int(it - cdf_.begin()) - 1, 0, n - 1);
  const float dx = 2 * radius_ / float(n);
  const float a = abs_[size_t(i)] / integral_, b = abs_[size_t(i) + 1] / integral_;
  // Within the segment the density is linear, a + (b - a) t; solve its CDF for t in [0, 1]:
  // dx (a t + (b - a) t^2 / 2) = u - cdf_i.
  const float target = (u - cdf_[size_t(i)]) / dx;
  float t;
  if (std::fabs(b - a) < 1e-6f * std::fmax(a, b)) {
    t = a > 0 ? target / a : 0.5f;
  } else {
    const float disc = std::fmax(0.0f, a * a + 2 * (b - a) * target);
    t = (std::sqrt(disc) - a) / (b - a);
  }
  t = std::clamp(t, 0.0f, 1.0f);
  pdf = a + (b - a) * t;
  return -radius_ + (float(i) + t) * dx;
}

float FilterSampler::sign_at(float x) const {
  const int n = int(f_.size()) - 1;
  const float s = (x + radius_) / (2 * radius_) * float(n);
  const int i = std::clamp(int(s), 0, n - 1);
  const float t = s - float(i);
  return (1 - t) * f_[size_t(i)] + t * f_[size_t(i) + 1] < 0.0f ? -1.0f : 1.0f;
}

FilterSample FilterSampler::sample(Vec2 u) const {
  float px, py;
  const float x = sample_1d(u.x, px), y = sample_1d(u.y, py);
  if (box_) return {{x, y}, 1.0f};
  // The filter is represented by its piecewise-linear interpolant f~, sampled exactly in
  // proportion to |f~|: the weight f~ / pdf is then +-(integral of |f~|)^2, the same magnitude for
  // every sample, so weights add no variance; only the signs of negative lobes remain.
  return {{x, y}, sign_at(x) * sign_at(y) * integral_ * integral_};
}

}  // namespace penumbra
