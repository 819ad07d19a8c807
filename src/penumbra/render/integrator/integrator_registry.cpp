#include "penumbra/render/integrator/integrator_registry.h"

#include <functional>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/params.h"
#include "penumbra/render/integrator/distribution_integrator.h"
#include "penumbra/render/integrator/raycast_integrator.h"
#include "penumbra/render/integrator/whitted_integrator.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Integrator>(const World&, const ParamList&,
                                                          const RenderSettings&)>;
struct Entry {
  IntegratorInfo info;
  Factory make;
};

/// Every integrator, written out explicitly: a new one is one line here.
const std::vector<Entry>& entries() {
  static const std::vector<Entry> all = {
      {{"raycast", "first hit shaded by normal, albedo or eye light (debugging view)"},
       [](const World& w, const ParamList& p, const RenderSettings&) {
         return std::make_unique<RaycastIntegrator>(w, p);
       }},
      {{"whitted", "recursive ray tracing: point lights, hard shadows, mirrors, refraction"},
       [](const World& w, const ParamList& p, const RenderSettings& s) {
         return std::make_unique<WhittedIntegrator>(w, p, s.max_depth);
       }},
      {{"distribution", "distribution ray tracing: soft shadows, glossy, translucency (Cook 1984)"},
       [](const World& w, const ParamList& p, const RenderSettings& s) {
         return std::make_unique<DistributionIntegrator>(w, p, s.max_depth);
       }},
  };
  return all;
}

}  // namespace

const std::vector<IntegratorInfo>& integrator_list() {
  static const std::vector<IntegratorInfo> list = [] {
    std::vector<IntegratorInfo> l;
    for (const auto& e : entries()) l.push_back(e.info);
    return l;
  }();
  return list;
}

std::unique_ptr<Integrator> make_integrator(std::string_view spec, const World& world,
                                            const RenderSettings& settings) {
  const ParamList params = ParamList::parse(spec);
  for (const auto& e : entries())
    if (e.info.name == params.name()) return e.make(world, params, settings);
  std::string names;
  for (const auto& e : entries()) names += (names.empty() ? "" : ", ") + e.info.name;
  throw Error(fmt::format("unknown integrator '{}' (valid: {})", params.name(), names));
}

}  // namespace penumbra
