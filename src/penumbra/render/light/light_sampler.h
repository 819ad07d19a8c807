#pragma once
/// Light selection: which of the world's lights a path samples at a vertex (pbrt-v4's
/// LightSampler: UniformLightSampler, PowerLightSampler).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/render/light/light.h"
#include "penumbra/render/sampling/alias_table.h"

namespace penumbra {

/// A light picked by LightSampler::sample, with the probability of picking it.
struct SampledLight {
  const Light* light = nullptr;  ///< null when there are no lights
  float pmf = 0;
};

/// Picks one light of a fixed list with a probability, in O(1), and answers the probability of a
/// given light in O(log n). Strategies: "power" (proportional to the luminance of power(); lights
/// of zero power are never picked; if every light has zero power, uniform) and "uniform".
/// Immutable and thread-safe; the lights must have been preprocessed (their power may depend on
/// the scene's bounds).
class LightSampler {
 public:
  /// The sampler of `lights` (each listed once) with the strategy `strategy`; throws Error for an
  /// unknown name, listing the valid ones.
  LightSampler(const std::vector<const Light*>& lights, const std::string& strategy);

  /// Picks a light with u in [0, 1); `u_remapped`, when given, receives the unused part of u, a
  /// fresh uniform number on [0, 1).
  SampledLight sample(float u, float* u_remapped = nullptr) const {
    // One light (a room with one lamp): the table's answer, bit for bit, without its
    // out-of-line call (perf put LightSampler::sample and AliasTable::sample at 2 % of a
    // Cornell-box render; a paired timing could not tell the difference from noise).
    if (single_) {
      if (u_remapped) *u_remapped = u < kOneMinusEpsilon ? u : kOneMinusEpsilon;
      return {single_, 1.0f};
    }
    return sample_table(u, u_remapped);
  }
  /// Probability that sample() picks `light` (zero for a light not in the list).
  float pmf(const Light* light) const {
    if (single_) return light == single_ ? 1.0f : 0.0f;
    return pmf_table(light);
  }
  /// The lights, in the order given.
  const std::vector<const Light*>& lights() const { return lights_; }
  /// The strategy's name.
  const std::string& strategy() const { return strategy_; }
  /// Names of the strategies.
  static std::vector<std::string> strategies();

 private:
  static constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
  SampledLight sample_table(float u, float* u_remapped) const;
  float pmf_table(const Light* light) const;

  const Light* single_ = nullptr;  ///< the light when there is exactly one
  std::vector<const Light*> lights_;
  std::vector<std::pair<const Light*, uint32_t>> index_;  ///< sorted by pointer
  AliasTable table_;
  std::string strategy_;
};

}  // namespace penumbra
