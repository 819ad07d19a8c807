#pragma once
/// One entry of a scene file's "shapes" array into a ShapeDesc: sphere, quad, inline mesh, or a
/// mesh read from an OBJ or PLY file (see docs/scene-format.md).
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/scene/json_value.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Parses the shape `v` found at `place` (e.g. "/shapes/3"): its keys, geometry, material (one of
/// `materials`), emission and transform. Mesh files are resolved relative to `base_dir`. Throws
/// InputError naming the JSON path of the first problem; errors inside a mesh file come from its
/// reader and name that file, and so do its warnings, appended to `warnings`.
ShapeDesc parse_shape(const nlohmann::json& v, const JsonPlace& place,
                      const std::set<std::string>& materials, const std::string& base_dir,
                      std::vector<std::string>& warnings);

}  // namespace penumbra
