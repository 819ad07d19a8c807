#include "penumbra/render/light/light_registry.h"

#include <functional>
#include <utility>

#include "penumbra/render/light/point_light.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Light>(const SceneParams&)>;

/// Every light type, written out explicitly: a new one is one line here.
const std::vector<std::pair<std::string, Factory>>& entries() {
  static const std::vector<std::pair<std::string, Factory>> all = {
      {"point", [](const SceneParams& p) { return std::make_unique<PointLight>(p); }},
  };
  return all;
}

}  // namespace

std::vector<std::string> light_types() {
  std::vector<std::string> names;
  for (const auto& [name, make] : entries()) names.push_back(name);
  return names;
}

std::unique_ptr<Light> make_light(const SceneParams& params) {
  for (const auto& [name, make] : entries())
    if (name == params.type()) return make(params);
  std::string valid;
  for (const auto& [name, make] : entries()) valid += (valid.empty() ? "" : ", ") + name;
  params.fail("type", "unknown light type '" + params.type() + "' (valid: " + valid + ")");
}

}  // namespace penumbra
