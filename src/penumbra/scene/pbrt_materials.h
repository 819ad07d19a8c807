#pragma once
/// pbrt-v4 materials and textures as penumbra materials (the JSON records the JSON loader holds).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/scene/pbrt_params.h"

namespace penumbra {

/// A named texture: the value a material parameter takes when it names the texture (a colour, a
/// number, or one of penumbra's texture objects).
struct PbrtTexture {
  nlohmann::json value;
  bool is_float = false;  ///< a "float" texture (else "spectrum")
};
using PbrtTextures = std::map<std::string, PbrtTexture>;

/// The texture of a `Texture "name" "spectrum|float" "class" ...` directive: constant,
/// checkerboard (uv mapping), scale of constants and spectrum imagemap (its file resolved in
/// `search_dirs`) are mapped; other classes are reported and stand for a mid grey.
PbrtTexture map_pbrt_texture(const std::string& value_type, const PbrtEntity& texture,
                             const PbrtTextures& textures,
                             const std::vector<std::string>& search_dirs,
                             std::vector<std::string>& warnings);

/// The penumbra material (a JSON object with "type") for a pbrt material of `material.type`:
/// diffuse, conductor, dielectric and rough dielectric exactly; thindielectric, coateddiffuse,
/// coatedconductor, diffusetransmission and measured by the nearest, with a warning. Returns
/// nullopt for "interface" (no surface) and "" types. Unknown types are an InputError.
std::optional<nlohmann::json> map_pbrt_material(const PbrtEntity& material,
                                                const PbrtTextures& textures,
                                                std::vector<std::string>& warnings);

}  // namespace penumbra
