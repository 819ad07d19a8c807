#pragma once
/// The registry of camera types named in scene files.
#include <memory>
#include <string>
#include <vector>

#include "penumbra/render/camera/camera.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Names of all camera types.
std::vector<std::string> camera_types();

/// Creates the camera that params.type() names for a width x height film; throws InputError for an
/// unknown type or a bad parameter.
std::unique_ptr<Camera> make_camera(const SceneParams& params, int width, int height);

}  // namespace penumbra
