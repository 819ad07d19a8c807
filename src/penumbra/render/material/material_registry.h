#pragma once
/// The registry of materials, by the type name used in scene files.
#include <memory>
#include <string>
#include <vector>

#include "penumbra/render/material/material.h"
#include "penumbra/scene/scene_desc.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Names of all material types, in registration order.
std::vector<std::string> material_types();

/// Creates the material that params.type() names; throws InputError for an unknown type (listing
/// the valid ones) or a bad parameter. Image textures may name one of `embedded` (a SceneDesc's
/// images).
std::unique_ptr<Material> make_material(const SceneParams& params,
                                        const std::vector<EmbeddedImage>* embedded = nullptr);

}  // namespace penumbra
