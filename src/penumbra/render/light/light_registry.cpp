#include "penumbra/render/light/light_registry.h"

#include <functional>

#include "penumbra/core/registry.h"
#include "penumbra/render/light/directional_light.h"
#include "penumbra/render/light/environment_light.h"
#include "penumbra/render/light/point_light.h"
#include "penumbra/render/light/spot_light.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Light>(const SceneParams&)>;

/// Every light type, written out explicitly: a new one is one line here.
const Registry<Factory>& registry() {
  static const Registry<Factory> all = {
      {"point", "", [](const SceneParams& p) { return std::make_unique<PointLight>(p); }},
      {"spot", "", [](const SceneParams& p) { return std::make_unique<SpotLight>(p); }},
      {"directional", "",
       [](const SceneParams& p) { return std::make_unique<DirectionalLight>(p); }},
      {"environment", "",
       [](const SceneParams& p) { return std::make_unique<EnvironmentLight>(p); }},
  };
  return all;
}

}  // namespace

std::vector<std::string> light_types() { return registry().names(); }

std::unique_ptr<Light> make_light(const SceneParams& params) {
  if (const Factory* make = registry().find(params.type())) return (*make)(params);
  params.fail("type", registry().unknown_name_message("light type", params.type()));
}

}  // namespace penumbra
