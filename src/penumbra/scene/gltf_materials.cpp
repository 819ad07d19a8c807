#include "penumbra/scene/gltf_materials.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

using nlohmann::json;

namespace {

// Roughness below this gives alpha = r^2 < 1e-3, which penumbra's microfacet materials treat as
// smooth; the smooth material is used then.
constexpr double kSmoothRoughness = 0.0316;

json rgb_json(Rgb c) {
  return json::array({c.r, c.g, c.b});
}

Rgb clamp01(Rgb c) {
  for (int i = 0; i < 3; ++i) c[i] = std::clamp(std::isfinite(c[i]) ? c[i] : 0.0f, 0.0f, 1.0f);
  return c;
}

// A number in an extension object, or `fallback`.
double extension_number(const tinygltf::Material& m, const char* ext, const char* key,
                        double fallback) {
  const auto it = m.extensions.find(ext);
  if (it == m.extensions.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
  const tinygltf::Value& v = it->second.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

// The names of the textures a material refers to that are not read, for the warning.
std::vector<std::string> unread_texture_names(const tinygltf::Material& m) {
  std::vector<std::string> out;
  if (m.pbrMetallicRoughness.metallicRoughnessTexture.index >= 0)
    out.push_back("metallicRoughnessTexture");
  if (m.normalTexture.index >= 0) out.push_back("normalTexture");
  if (m.occlusionTexture.index >= 0) out.push_back("occlusionTexture");
  if (m.emissiveTexture.index >= 0) out.push_back("emissiveTexture");
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

json gltf_material_params(Rgb base_color, double metallic, double roughness, double transmission,
                          double ior) {
  base_color = clamp01(base_color);
  roughness = std::clamp(roughness, 0.0, 1.0);
  if (transmission > 0.0 && metallic < 0.5) {
    json p = {{"ior", ior}};
    if (!(base_color.r == 1 && base_color.g == 1 && base_color.b == 1))
      p["tint"] = rgb_json(base_color);
    if (roughness < kSmoothRoughness) {
      p["type"] = "dielectric";
    } else {
      p["type"] = "rough_dielectric";
      p["roughness"] = roughness;
    }
    return p;
  }
  if (metallic >= 0.5)
    return {{"type", "conductor"}, {"reflectance", rgb_json(base_color)}, {"roughness", roughness}};
  return {{"type", "diffuse"}, {"albedo", rgb_json(base_color)}};
}

GltfMaterialUse gltf_default_material(const std::string& file,
                                      std::vector<MaterialDesc>& materials) {
  const std::string name = "gltf/default";
  const bool present = std::any_of(materials.begin(), materials.end(),
                                   [&](const MaterialDesc& m) { return m.name == name; });
  if (!present)
    materials.push_back({name, SceneParams(gltf_material_params(Rgb(1.0f), 1.0, 1.0, 0.0, 1.5),
                                           file, "/materials/default")});
  return {name, std::nullopt, false};
}

namespace {

// The material's parameters with its base colour texture, when it has a usable one: the diffuse
// albedo or the conductor's reflectance (F0) become the image times baseColorFactor.
void add_base_color_texture(const GltfSource& src, GltfTextures& textures,
                            const tinygltf::Material& m, const std::string& at, Rgb base,
                            json& params, std::vector<std::string>& warnings) {
  const tinygltf::TextureInfo& info = m.pbrMetallicRoughness.baseColorTexture;
  if (info.index < 0) return;
  const std::string tex_at = at + "/pbrMetallicRoughness/baseColorTexture";
  const char* key = params["type"] == "diffuse"     ? "albedo"
                    : params["type"] == "conductor" ? "reflectance"
                                                    : nullptr;
  if (!key) {
    warnings.push_back(src.message(tex_at, "not read for a transmissive material (" +
                                               params["type"].get<std::string>() +
                                               "): baseColorFactor used"));
    return;
  }
  if (std::optional<json> t = textures.texture(info, tex_at, clamp01(base), warnings))
    params[key] = std::move(*t);
}

}  // namespace

std::vector<GltfMaterialUse> map_gltf_materials(const GltfSource& src, GltfTextures& textures,
                                                std::vector<MaterialDesc>& materials,
                                                std::vector<std::string>& warnings) {
  std::vector<GltfMaterialUse> out;
  for (size_t i = 0; i < src.model.materials.size(); ++i) {
    const tinygltf::Material& m = src.model.materials[i];
    const std::string at = "/materials/" + std::to_string(i);
    const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
    // Base colour (linear RGB; alpha is not used).
    Rgb base(1.0f);
    if (pbr.baseColorFactor.size() >= 3)
      base = Rgb(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                 float(pbr.baseColorFactor[2]));
    const double metallic = pbr.metallicFactor;
    if (metallic > 0.0 && metallic < 1.0)
      warnings.push_back(src.message(at + "/pbrMetallicRoughness/metallicFactor",
                                     "metallic " + std::to_string(metallic) +
                                         " is not 0 or 1: taken as " +
                                         (metallic >= 0.5 ? "1 (conductor)" : "0 (diffuse)")));
    const double transmission =
        extension_number(m, "KHR_materials_transmission", "transmissionFactor", 0.0);
    const double ior = extension_number(m, "KHR_materials_ior", "ior", 1.5);
    if (transmission > 0.0 && transmission < 1.0 && metallic < 0.5)
      warnings.push_back(src.message(
          at + "/extensions/KHR_materials_transmission",
          "transmissionFactor " + std::to_string(transmission) + " taken as 1 (a dielectric)"));
    if (!(ior > 0.0 && ior < 100.0))
      src.fail(at + "/extensions/KHR_materials_ior/ior", "must lie in (0, 100)");
    const std::vector<std::string> unread = unread_texture_names(m);
    if (!unread.empty())
      warnings.push_back(
          src.message(at, "textures are not read (" + join(unread) + "): factors used"));
    if (m.alphaMode == "BLEND" || m.alphaMode == "MASK")
      warnings.push_back(
          src.message(at + "/alphaMode", m.alphaMode + " ignored: opaque (alpha is dropped)"));
    GltfMaterialUse use;
    use.material = "gltf/" + std::to_string(i);
    json params = gltf_material_params(base, metallic, pbr.roughnessFactor, transmission, ior);
    add_base_color_texture(src, textures, m, at, base, params, warnings);
    materials.push_back({use.material, SceneParams(std::move(params), src.file, at)});
    // Emission: emissiveFactor scaled by KHR_materials_emissive_strength.
    const double strength =
        extension_number(m, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
    if (m.emissiveFactor.size() == 3) {
      Rgb e(float(m.emissiveFactor[0] * strength), float(m.emissiveFactor[1] * strength),
            float(m.emissiveFactor[2] * strength));
      for (int c = 0; c < 3; ++c)
        if (!(std::isfinite(e[c]) && e[c] >= 0.0f))
          src.fail(at + "/emissiveFactor", "emission must be finite and non-negative");
      if (e.r > 0 || e.g > 0 || e.b > 0) use.emission = e;
    }
    use.two_sided_emission = m.doubleSided;
    out.push_back(std::move(use));
  }
  return out;
}

}  // namespace penumbra
