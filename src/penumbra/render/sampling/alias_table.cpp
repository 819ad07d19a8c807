#include "penumbra/render/sampling/alias_table.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
}  // namespace

AliasTable::AliasTable(std::span<const float> weights) {
  const size_t n = weights.size();
  bins_.resize(n);
  if (n == 0) return;
  // Normalise in double; unusable weights count as zero, and all-zero means uniform.
  std::vector<double> p(n);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const float w = weights[i];
    p[i] = w > 0.0f && std::isfinite(w) ? double(w) : 0.0;
    sum += p[i];
  }
  if (!(sum > 0.0)) std::fill(p.begin(), p.end(), 1.0), sum = double(n);
  for (size_t i = 0; i < n; ++i) {
    p[i] /= sum;
    bins_[i].p = float(p[i]);
  }

  // Vose's construction: each under-full bin (scaled probability < 1) is topped up by an over-full
  // item, which then goes back on the list it now belongs to. Index stacks keep it deterministic.
  std::vector<uint32_t> under, over;
  std::vector<double> scaled(n);
  for (size_t i = 0; i < n; ++i) {
    scaled[i] = p[i] * double(n);
    (scaled[i] < 1.0 ? under : over).push_back(uint32_t(i));
  }
  while (!under.empty() && !over.empty()) {
    const uint32_t s = under.back(), l = over.back();
    under.pop_back(), over.pop_back();
    bins_[s].q = float(scaled[s]);
    bins_[s].alias = l;
    scaled[l] = (scaled[l] + scaled[s]) - 1.0;
    (scaled[l] < 1.0 ? under : over).push_back(l);
  }
  // What is left is full up to rounding: keep its own item always.
  for (uint32_t i : under) bins_[i].q = 1.0f, bins_[i].alias = i;
  for (uint32_t i : over) bins_[i].q = 1.0f, bins_[i].alias = i;
}

uint32_t AliasTable::sample(float u, float* pmf, float* u_remapped) const {
  // The bin from the integer part of u n, the choice within it from the fraction, which is then
  // stretched back to [0, 1) for reuse.
  const uint32_t n = size();
  const uint32_t bin = std::min(uint32_t(u * float(n)), n - 1);
  const float up = std::min(u * float(n) - float(bin), kOneMinusEpsilon);
  const Bin& b = bins_[bin];
  if (up < b.q) {
    if (pmf) *pmf = b.p;
    if (u_remapped) *u_remapped = std::min(up / b.q, kOneMinusEpsilon);
    return bin;
  }
  if (pmf) *pmf = bins_[b.alias].p;
  if (u_remapped) *u_remapped = std::min((up - b.q) / (1.0f - b.q), kOneMinusEpsilon);
  return b.alias;
}

}  // namespace penumbra
