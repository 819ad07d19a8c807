#pragma once
/// Writing a SceneDesc back out as penumbra's JSON scene format, with its triangle meshes as PLY
/// files: what `penumbra convert` writes, so that a scene read from any format (pbrt-v4, glTF)
/// becomes a JSON scene that loads to the same SceneDesc.
#include <string>
#include <vector>

#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// A file of a written scene: its path relative to the scene file's folder, and its bytes.
struct SceneFile {
  std::string path;
  std::string bytes;
};

/// The JSON scene file for `scene` (the first element, path `json_name`) and one binary PLY file
/// per triangle mesh (`mesh_dir`/shape-N.ply for the N-th shape, `mesh_dir`/object-O-S.ply for
/// shape S of object O), referenced from the JSON by those relative paths. Spheres and quads are
/// written inline; every transform as its 16 numbers ({"matrix": ...}, doubles that round-trip);
/// the camera, materials and lights as their parameter objects, with the files they name
/// (environment maps, image textures) made absolute. Embedded images (glTF) are written as they
/// are to `mesh_dir`/image-N.png or .jpg and textures name those files. Reading the result with
/// load_scene gives the same shapes, meshes (bit for bit), materials, lights, camera and render
/// settings.
std::vector<SceneFile> write_scene_json(const SceneDesc& scene, const std::string& json_name,
                                        const std::string& mesh_dir);

}  // namespace penumbra
