#pragma once
/// The parts of a glTF scene around its geometry: the camera (the first camera node, else one that
/// frames the scene), KHR_lights_punctual lights, and the default lighting and render settings of a
/// file that has none.
#include <string>
#include <vector>

#include "penumbra/scene/gltf_nodes.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Sets scene.camera (and the resolution from its aspect ratio) from the first node in `visits`
/// that has a perspective camera; returns false when there is none.
bool map_gltf_camera(const GltfSource& src, const std::vector<GltfNodeVisit>& visits,
                     SceneDesc& scene);

/// Appends a penumbra light for every node in `visits` with a KHR_lights_punctual light.
void map_gltf_lights(const GltfSource& src, const std::vector<GltfNodeVisit>& visits,
                     SceneDesc& scene);

/// A pinhole camera (vfov 40 degrees) looking at the centre of the scene's bounds from +z and a
/// little above, far enough back that the bounding sphere fits the field of view.
void set_default_gltf_camera(SceneDesc& scene);

}  // namespace penumbra
