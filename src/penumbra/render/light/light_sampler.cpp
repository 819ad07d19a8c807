#include "penumbra/render/light/light_sampler.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "penumbra/core/error.h"

namespace penumbra {

namespace {
/// Selection weight of a light under "power": the luminance of its power, zero if unusable.
float power_weight(const Light& light) {
  const float w = light.power().luminance();
  return w > 0.0f && std::isfinite(w) ? w : 0.0f;
}
}  // namespace

std::vector<std::string> LightSampler::strategies() {
  return {"power", "uniform"};
}

LightSampler::LightSampler(const std::vector<const Light*>& lights, const std::string& strategy)
    : lights_(lights), strategy_(strategy) {
  std::vector<float> weights(lights_.size(), 1.0f);
  if (strategy == "power") {
    // All-zero weights make the alias table uniform, the fallback we want.
    for (size_t i = 0; i < lights_.size(); ++i) weights[i] = power_weight(*lights_[i]);
  } else if (strategy != "uniform") {
    throw Error("unknown light sampler '" + strategy + "' (valid: power, uniform)");
  }
  table_ = AliasTable(weights);
  if (lights_.size() == 1) single_ = lights_[0];
  index_.reserve(lights_.size());
  for (size_t i = 0; i < lights_.size(); ++i) index_.emplace_back(lights_[i], uint32_t(i));
  std::sort(index_.begin(), index_.end(), [](const auto& a, const auto& b) {
    return std::less<const Light*>()(a.first, b.first);
  });
}

SampledLight LightSampler::sample_table(float u, float* u_remapped) const {
  if (lights_.empty()) {
    if (u_remapped) *u_remapped = u;
    return {};
  }
  SampledLight s;
  s.light = lights_[table_.sample(u, &s.pmf, u_remapped)];
  return s;
}

float LightSampler::pmf_table(const Light* light) const {
  const auto it = std::lower_bound(
      index_.begin(), index_.end(), light,
      [](const auto& entry, const Light* l) { return std::less<const Light*>()(entry.first, l); });
  if (it == index_.end() || it->first != light) return 0.0f;
  return table_.pmf(it->second);
}

}  // namespace penumbra
