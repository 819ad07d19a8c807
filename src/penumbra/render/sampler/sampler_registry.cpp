#include "penumbra/render/sampler/sampler_registry.h"

#include <functional>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/params.h"
#include "penumbra/render/sampler/independent_sampler.h"
#include "penumbra/render/sampler/sobol_sampler.h"
#include "penumbra/render/sampler/stratified_sampler.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Sampler>(int, uint64_t)>;
struct Entry {
  SamplerInfo info;
  Factory make;
};

/// Every sampler, written out explicitly: a new one is one line here.
const std::vector<Entry>& entries() {
  static const std::vector<Entry> all = {
      {{"independent", "uniform random numbers (the lecture's 'random')"},
       [](int spp, uint64_t seed) { return std::make_unique<IndependentSampler>(spp, seed); }},
      {{"regular", "stratum centres on an nx x ny grid: uniform supersampling, aliases"},
       [](int spp, uint64_t seed) { return std::make_unique<StratifiedSampler>(spp, seed, false); }},
      {{"jittered", "one uniform point in each of nx x ny strata (stratified sampling)"},
       [](int spp, uint64_t seed) { return std::make_unique<StratifiedSampler>(spp, seed, true); }},
      {{"sobol", "Owen-scrambled (0,2)-sequence per dimension pair (low discrepancy)"},
       [](int spp, uint64_t seed) { return std::make_unique<SobolSampler>(spp, seed); }},
  };
  return all;
}

}  // namespace

const std::vector<SamplerInfo>& sampler_list() {
  static const std::vector<SamplerInfo> list = [] {
    std::vector<SamplerInfo> l;
    for (const auto& e : entries()) l.push_back(e.info);
    return l;
  }();
  return list;
}

std::unique_ptr<Sampler> make_sampler(std::string_view spec, int spp, uint64_t seed) {
  const ParamList params = ParamList::parse(spec);
  params.check_all_used();
  const std::string name = params.name() == "random" ? "independent" : params.name();
  for (const auto& e : entries())
    if (e.info.name == name) return e.make(spp, seed);
  std::string names;
  for (const auto& e : entries()) names += (names.empty() ? "" : ", ") + e.info.name;
  throw Error(fmt::format("unknown sampler '{}' (valid: {})", params.name(), names));
}

}  // namespace penumbra
