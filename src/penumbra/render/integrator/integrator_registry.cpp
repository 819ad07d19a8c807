#include "penumbra/render/integrator/integrator_registry.h"

#include <functional>

#include "penumbra/core/params.h"
#include "penumbra/core/registry.h"
#include "penumbra/render/integrator/distribution_integrator.h"
#include "penumbra/render/integrator/path_integrator.h"
#include "penumbra/render/integrator/photon_integrator.h"
#include "penumbra/render/integrator/raycast_integrator.h"
#include "penumbra/render/integrator/sppm_integrator.h"
#include "penumbra/render/radiosity/radiosity_integrator.h"
#include "penumbra/render/integrator/whitted_integrator.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Integrator>(const World&, const ParamList&,
                                                          const RenderSettings&)>;

/// Every integrator, written out explicitly: a new one is one line here.
const Registry<Factory>& registry() {
  static const Registry<Factory> all = {
      {"raycast", "first hit shaded by normal, albedo or eye light (debugging view)",
       [](const World& w, const ParamList& p, const RenderSettings&) {
         return std::make_unique<RaycastIntegrator>(w, p);
       }},
      {"whitted", "recursive ray tracing: point lights, hard shadows, mirrors, refraction",
       [](const World& w, const ParamList& p, const RenderSettings& s) {
         return std::make_unique<WhittedIntegrator>(
             w, p, s.max_depth.value_or(RenderSettings::kDefaultMaxDepth));
       }},
      {"distribution", "distribution ray tracing: soft shadows, glossy, translucency (Cook 1984)",
       [](const World& w, const ParamList& p, const RenderSettings& s) {
         return std::make_unique<DistributionIntegrator>(
             w, p, s.max_depth.value_or(RenderSettings::kDefaultMaxDepth));
       }},
      {"path", "path tracing: the rendering equation, unbiased, with MIS (Kajiya 1986, Veach 1997)",
       [](const World& w, const ParamList& p, const RenderSettings& s) {
         return std::make_unique<PathIntegrator>(w, p, s.max_depth.value_or(-1));
       }},
      {"photon", "photon mapping: caustic and global maps, final gathering (Jensen 1996)",
       [](const World& w, const ParamList& p, const RenderSettings& s) {
         return std::make_unique<PhotonIntegrator>(w, p, s);
       }},
      {"sppm", "stochastic progressive photon mapping (Hachisuka, Jensen 2009)",
       [](const World& w, const ParamList& p, const RenderSettings& s) {
         return std::make_unique<SppmIntegrator>(w, p, s);
       }},
      {"radiosity", "radiosity: diffuse patches, form factors, a linear solve (Goral et al. 1984)",
       [](const World& w, const ParamList& p, const RenderSettings& s) {
         return std::make_unique<RadiosityIntegrator>(w, p, s);
       }},
  };
  return all;
}

}  // namespace

const std::vector<IntegratorInfo>& integrator_list() {
  static const std::vector<IntegratorInfo> list = [] {
    std::vector<IntegratorInfo> l;
    for (const auto& e : registry().entries()) l.push_back({e.name, e.description});
    return l;
  }();
  return list;
}

std::unique_ptr<Integrator> make_integrator(std::string_view spec, const World& world,
                                            const RenderSettings& settings) {
  const ParamList params = ParamList::parse(spec);
  return registry().get(params.name(), "integrator")(world, params, settings);
}

}  // namespace penumbra
