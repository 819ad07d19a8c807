#include "penumbra/render/material/material_registry.h"

#include <functional>
#include <type_traits>

#include "penumbra/core/registry.h"
#include "penumbra/render/material/conductor_material.h"
#include "penumbra/render/material/dielectric_material.h"
#include "penumbra/render/material/diffuse_material.h"
#include "penumbra/render/material/mirror_material.h"
#include "penumbra/render/material/rough_dielectric_material.h"

namespace penumbra {

namespace {

using Images = std::vector<EmbeddedImage>;
using Factory = std::function<std::unique_ptr<Material>(const SceneParams&, const Images*)>;

// Materials with textures take the scene's embedded images; the others only their parameters.
template <class T>
std::unique_ptr<Material> create(const SceneParams& p, const Images* embedded) {
  if constexpr (std::is_constructible_v<T, const SceneParams&, const Images*>)
    return std::make_unique<T>(p, embedded);
  else
    return std::make_unique<T>(p);
}

/// Every material type, written out explicitly: a new one is one line here.
const Registry<Factory>& registry() {
  static const Registry<Factory> all = {
      {"diffuse", "", create<DiffuseMaterial>},
      {"mirror", "", create<MirrorMaterial>},
      {"dielectric", "", create<DielectricMaterial>},
      {"conductor", "", create<ConductorMaterial>},
      {"rough_dielectric", "", create<RoughDielectricMaterial>},
  };
  return all;
}

}  // namespace

std::vector<std::string> material_types() {
  return registry().names();
}

std::unique_ptr<Material> make_material(const SceneParams& params, const Images* embedded) {
  if (const Factory* make = registry().find(params.type())) return (*make)(params, embedded);
  params.fail("type", registry().unknown_name_message("material type", params.type()));
}

}  // namespace penumbra
