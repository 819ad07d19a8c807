#pragma once
/// The registry of pixel samplers, chosen with --sampler NAME or the scene's "sampler".
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/render/sampler/sampler.h"

namespace penumbra {

/// One registered sampler.
struct SamplerInfo {
  std::string name;
  std::string description;
};

/// All registered samplers, in registration order.
const std::vector<SamplerInfo>& sampler_list();

/// Creates the sampler named by `spec` for `spp` samples per pixel and `seed`; throws Error for
/// an unknown name (listing the valid ones) or a bad parameter.
std::unique_ptr<Sampler> make_sampler(std::string_view spec, int spp, uint64_t seed);

}  // namespace penumbra
