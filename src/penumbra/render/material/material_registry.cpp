#include "penumbra/render/material/material_registry.h"

#include <functional>
#include <utility>

#include "penumbra/render/material/conductor_material.h"
#include "penumbra/render/material/dielectric_material.h"
#include "penumbra/render/material/diffuse_material.h"
#include "penumbra/render/material/mirror_material.h"
#include "penumbra/render/material/rough_dielectric_material.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Material>(const SceneParams&)>;

template <class T>
std::unique_ptr<Material> create(const SceneParams& p) {
  return std::make_unique<T>(p);
}

/// Every material type, written out explicitly: a new one is one line here.
const std::vector<std::pair<std::string, Factory>>& entries() {
  static const std::vector<std::pair<std::string, Factory>> all = {
      {"diffuse", create<DiffuseMaterial>},
      {"mirror", create<MirrorMaterial>},
      {"dielectric", create<DielectricMaterial>},
      {"conductor", create<ConductorMaterial>},
      {"rough_dielectric", create<RoughDielectricMaterial>},
  };
  return all;
}

}  // namespace

std::vector<std::string> material_types() {
  std::vector<std::string> names;
  for (const auto& [name, make] : entries()) names.push_back(name);
  return names;
}

std::unique_ptr<Material> make_material(const SceneParams& params) {
  for (const auto& [name, make] : entries())
    if (name == params.type()) return make(params);
  std::string valid;
  for (const auto& [name, make] : entries()) valid += (valid.empty() ? "" : ", ") + name;
  params.fail("type", "unknown material type '" + params.type() + "' (valid: " + valid + ")");
}

}  // namespace penumbra
