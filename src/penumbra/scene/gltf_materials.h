#pragma once
/// glTF materials (pbrMetallicRoughness, emission, KHR_materials_emissive_strength,
/// KHR_materials_transmission, KHR_materials_ior) as penumbra MaterialDescs, plus the emission a
/// shape that uses them carries. The base colour texture becomes an image texture of the diffuse
/// albedo or the conductor's F0; the other textures are not read: their factors are used, with a
/// warning.
#include <optional>
#include <string>
#include <vector>

#include "penumbra/scene/gltf_accessors.h"
#include "penumbra/scene/gltf_textures.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// What a primitive that uses one glTF material takes from it.
struct GltfMaterialUse {
  std::string material;         ///< the MaterialDesc's name
  std::optional<Rgb> emission;  ///< emissiveFactor times emissiveStrength, when not black
  bool two_sided_emission = false;
};

/// Maps every glTF material to a MaterialDesc named "gltf/N" (appended to `materials`), in order,
/// its base colour texture through `textures`; approximations and ignored features go to
/// `warnings`.
std::vector<GltfMaterialUse> map_gltf_materials(const GltfSource& src, GltfTextures& textures,
                                                std::vector<MaterialDesc>& materials,
                                                std::vector<std::string>& warnings);

/// The material of primitives without one: the glTF default material (a material with no
/// properties: base colour 1, metallic 1, roughness 1), added as "gltf/default" when first used.
GltfMaterialUse gltf_default_material(const std::string& file,
                                      std::vector<MaterialDesc>& materials);

/// The MaterialDesc parameters of a pbrMetallicRoughness material with these factors (also used
/// for the default material): conductor when metallic >= 0.5, else diffuse; dielectric or
/// rough_dielectric when transmission > 0.
nlohmann::json gltf_material_params(Rgb base_color, double metallic, double roughness,
                                    double transmission, double ior);

}  // namespace penumbra
