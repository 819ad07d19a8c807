#pragma once
/// Named objects and their instances in a scene file: the top-level "objects" map (each a list of
/// ordinary shapes) and the shape entries of type "instance" that place one (see
/// docs/scene-format.md).
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/scene/json_value.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Parses the "objects" map `v` at `place`: each member {"shapes": [...]} of static,
/// non-emissive shapes (no nested instances). Throws InputError naming the JSON path; the warnings
/// of mesh files are appended to `warnings`.
std::vector<ObjectDesc> parse_objects(const nlohmann::json& v, const JsonPlace& place,
                                      const std::set<std::string>& materials,
                                      const std::string& base_dir,
                                      std::vector<std::string>& warnings);

/// True when the shape entry `v` is an instance ({"type": "instance"}).
bool is_instance_entry(const nlohmann::json& v);

/// Parses the instance entry `v` at `place`: "object" (one of `objects`), optional "transform"
/// and "name". Throws InputError naming the JSON path.
InstanceDesc parse_instance(const nlohmann::json& v, const JsonPlace& place,
                            const std::vector<ObjectDesc>& objects);

}  // namespace penumbra
