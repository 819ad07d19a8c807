#pragma once
/// The JSON scene loader: reads a scene file (docs/scene-format.md) into a plain SceneDesc.
///
/// The loader parses and validates the sections whose keys are fixed ("render", "shapes", the top
/// level); cameras, materials and lights are kept as SceneParams (a type plus its raw object) for
/// the renderer's factories, which read and check their own keys. Every error is an InputError
/// "FILE:/json/path: problem" (syntax errors: "FILE:LINE:COLUMN: problem"). The warnings of mesh
/// files (obj_reader.h) go to SceneDesc::warnings.
#include <string>

#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Reads the scene file at `path`; mesh files are resolved relative to its directory. A `.pbrt`
/// file (any case) is read by the pbrt-v4 reader (pbrt_parser.h), a `.gltf` or `.glb` file by the
/// glTF 2.0 reader (gltf_loader.h), anything else as JSON.
SceneDesc load_scene(const std::string& path);

/// Parses scene JSON held in memory; `file_name` names it in messages and `base_dir` is the
/// directory that relative mesh file paths start from ("" for the working directory).
SceneDesc parse_scene(const std::string& json_text, const std::string& file_name,
                      const std::string& base_dir);

}  // namespace penumbra
