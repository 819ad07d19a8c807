#include "penumbra/render/sampler/sampler_registry.h"

#include <functional>

#include "penumbra/core/params.h"
#include "penumbra/core/registry.h"
#include "penumbra/render/sampler/independent_sampler.h"
#include "penumbra/render/sampler/sobol_sampler.h"
#include "penumbra/render/sampler/stratified_sampler.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Sampler>(int, uint64_t)>;

/// Every sampler, written out explicitly: a new one is one line here.
const Registry<Factory>& registry() {
  static const Registry<Factory> all = {
      {"independent", "uniform random numbers (the lecture's 'random')",
       [](int spp, uint64_t seed) { return std::make_unique<IndependentSampler>(spp, seed); }},
      {"regular", "stratum centres on an nx x ny grid: uniform supersampling, aliases",
       [](int spp, uint64_t seed) {
         return std::make_unique<StratifiedSampler>(spp, seed, false);
       }},
      {"jittered", "one uniform point in each of nx x ny strata (stratified sampling)",
       [](int spp, uint64_t seed) { return std::make_unique<StratifiedSampler>(spp, seed, true); }},
      {"sobol", "Owen-scrambled (0,2)-sequence per dimension pair (low discrepancy)",
       [](int spp, uint64_t seed) { return std::make_unique<SobolSampler>(spp, seed); }},
  };
  return all;
}

}  // namespace

const std::vector<SamplerInfo>& sampler_list() {
  static const std::vector<SamplerInfo> list = [] {
    std::vector<SamplerInfo> l;
    for (const auto& e : registry().entries()) l.push_back({e.name, e.description});
    return l;
  }();
  return list;
}

std::unique_ptr<Sampler> make_sampler(std::string_view spec, int spp, uint64_t seed) {
  const ParamList params = ParamList::parse(spec);
  params.check_all_used();
  const std::string name = params.name() == "random" ? "independent" : params.name();
  return registry().get(name, "sampler")(spp, seed);
}

}  // namespace penumbra
