#pragma once
/// Sampling a discrete distribution in constant time: the alias method (Walker 1977, "An Efficient
/// Method for Generating Discrete Random Variables with General Distributions"), built with Vose's
/// stable O(n) construction (Vose 1991, "A Linear Algorithm for Generating Random Numbers with a
/// Given Distribution"), as pbrt-v4's AliasTable.
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

/// A discrete distribution over 0..size()-1 with probabilities proportional to the weights it was
/// built from. Deterministic: the same weights give the same table and the same samples.
class AliasTable {
 public:
  AliasTable() = default;
  /// The table of `weights`. Negative, NaN and infinite weights count as zero; when no weight is
  /// positive every item gets the same probability.
  explicit AliasTable(std::span<const float> weights);

  /// Picks an item with one uniform number u in [0, 1); `pmf` receives its probability and
  /// `u_remapped` the unused part of u, again uniform on [0, 1) and independent of the choice.
  /// Requires size() > 0.
  uint32_t sample(float u, float* pmf = nullptr, float* u_remapped = nullptr) const;
  /// Probability of item i.
  float pmf(uint32_t i) const { return bins_[i].p; }
  /// Number of items.
  uint32_t size() const { return static_cast<uint32_t>(bins_.size()); }

 private:
  /// One of n equal-probability bins: keep item i with probability q, else take `alias`.
  struct Bin {
    float q = 1;         ///< probability of keeping the bin's own item
    float p = 0;         ///< the bin's own item's probability
    uint32_t alias = 0;  ///< the item taken otherwise
  };
  std::vector<Bin> bins_;
};

}  // namespace penumbra
