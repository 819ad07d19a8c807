#pragma once
/// The glTF 2.0 scene reader (docs/gltf-import.md): .gltf (JSON with external or data: buffers)
/// and .glb files, producing the same plain SceneDesc as the JSON loader: meshes as triangle
/// meshes (instanced when several nodes share one), the node hierarchy's transforms, the first
/// camera, KHR_lights_punctual lights and pbrMetallicRoughness materials. Errors are InputErrors
/// "FILE:/json/path: problem"; what is skipped or approximated is reported in SceneDesc::warnings.
#include <string>

#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Reads the glTF file at `path`; external buffers are resolved in its directory.
SceneDesc load_gltf_scene(const std::string& path);

/// Parses a glTF file held in memory (a .glb when it starts with "glTF", else JSON text);
/// `file_name` names it in messages and `base_dir` is the directory buffer URIs start from ("" for
/// the working directory).
SceneDesc parse_gltf_scene(const std::string& bytes, const std::string& file_name,
                           const std::string& base_dir);

}  // namespace penumbra
