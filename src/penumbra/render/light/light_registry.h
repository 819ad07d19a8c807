#pragma once
/// The registry of light types named in scene files' "lights" section.
#include <memory>
#include <string>
#include <vector>

#include "penumbra/render/light/light.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Names of all light types.
std::vector<std::string> light_types();

/// Creates the light that params.type() names; throws InputError for an unknown type or a bad
/// parameter. (Emissive shapes are not made here: they belong to the shapes section.)
std::unique_ptr<Light> make_light(const SceneParams& params);

}  // namespace penumbra
