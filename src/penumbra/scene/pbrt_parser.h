#pragma once
/// The pbrt-v4 scene reader (docs/pbrt-import.md): directives, the graphics state (transforms,
/// attributes, materials, area lights, named coordinate systems) and Include/Import, producing the
/// same plain SceneDesc as the JSON loader. Errors are InputErrors "FILE:LINE:COLUMN: problem";
/// what is skipped or approximated is reported in SceneDesc::warnings.
#include <string>

#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Reads the pbrt file at `path`; Include, Import and mesh files are resolved relative to the
/// including file's directory, then to the directory of `path`.
SceneDesc load_pbrt_scene(const std::string& path);

/// Parses pbrt text held in memory; `file_name` names it in messages and `base_dir` is the
/// directory relative file names start from ("" for the working directory).
SceneDesc parse_pbrt_scene(const std::string& text, const std::string& file_name,
                           const std::string& base_dir);

}  // namespace penumbra
