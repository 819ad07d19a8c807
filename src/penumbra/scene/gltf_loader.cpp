#include "penumbra/scene/gltf_loader.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <set>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/scene/gltf_materials.h"
#include "penumbra/scene/gltf_meshes.h"
#include "penumbra/scene/gltf_model.h"
#include "penumbra/scene/gltf_textures.h"
#include "penumbra/scene/gltf_view.h"
#include "penumbra/scene/mesh_reader.h"

namespace penumbra {

namespace {

// tinygltf reads "extras" and "extensions" into its Value tree recursively; deeper nesting than
// this is refused before it can exhaust the stack.
constexpr int kMaxJsonDepth = 256;

const std::set<std::string> kSupportedExtensions = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_transmission",
    "KHR_materials_ior"};

// The JSON text of the file: all of it, or a .glb's first chunk (as far as the file goes).
std::string_view json_part(std::string_view bytes) {
  if (bytes.size() < 20 || bytes.substr(0, 4) != "glTF") return bytes;
  uint32_t length;
  std::memcpy(&length, bytes.data() + 12, 4);
  return bytes.substr(20, std::min<size_t>(length, bytes.size() - 20));
}

void check_nesting(std::string_view text, const std::string& file) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw InputError(file, "byte " + std::to_string(i),
                         "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

void warn_unsupported(const GltfSource& src, std::vector<std::string>& warnings) {
  const tinygltf::Model& m = src.model;
  for (size_t i = 0; i < m.extensionsRequired.size(); ++i)
    if (!kSupportedExtensions.count(m.extensionsRequired[i]))
      warnings.push_back(src.message(
          "/extensionsRequired/" + std::to_string(i),
          "required extension " + m.extensionsRequired[i] + " not supported: rendering the rest"));
  for (size_t i = 0; i < m.extensionsUsed.size(); ++i)
    if (!kSupportedExtensions.count(m.extensionsUsed[i]) &&
        std::find(m.extensionsRequired.begin(), m.extensionsRequired.end(), m.extensionsUsed[i]) ==
            m.extensionsRequired.end())
      warnings.push_back(src.message("/extensionsUsed/" + std::to_string(i),
                                     "extension " + m.extensionsUsed[i] + " not supported"));
  if (!m.animations.empty())
    warnings.push_back(src.message("/animations", "animations ignored (the rest pose is used)"));
  if (!m.skins.empty()) warnings.push_back(src.message("/skins", "skins ignored"));
}

ShapeDesc make_shape(const GltfPrimitive& p, const GltfMaterialUse& use, const Transform& t,
                     const std::string& name) {
  ShapeDesc s;
  s.geometry = p.mesh;
  s.to_world = t;
  s.material = use.material;
  s.emission = use.emission;
  s.two_sided_emission = use.emission ? use.two_sided_emission : false;
  s.path = p.path;
  s.name = name;
  return s;
}

// Meshes: one used by a single node (or emissive) becomes plain shapes with the node's world
// transform; one used by several becomes an object placed by one instance per node.
void map_meshes(const GltfSource& src, const std::string& base_dir,
                const std::vector<GltfNodeVisit>& visits, SceneDesc& scene) {
  const tinygltf::Model& m = src.model;
  GltfTextures textures(src, base_dir, scene.images);
  const std::vector<GltfMaterialUse> uses =
      map_gltf_materials(src, textures, scene.materials, scene.warnings);
  std::vector<std::vector<std::pair<const GltfNodeVisit*, Transform>>> users(m.meshes.size());
  for (const GltfNodeVisit& v : visits) {
    const int mesh = m.nodes[size_t(v.node)].mesh;
    if (mesh < 0) continue;
    if (size_t(mesh) >= m.meshes.size())
      src.fail(v.path + "/mesh", "mesh " + std::to_string(mesh) + " out of range (" +
                                     std::to_string(m.meshes.size()) + " meshes)");
    try {
      users[size_t(mesh)].push_back({&v, Transform(v.world)});
    } catch (const InputError&) {
      throw;
    } catch (const Error&) {
      scene.warnings.push_back(src.message(v.path, "singular transform: mesh skipped"));
    }
  }
  for (size_t mi = 0; mi < m.meshes.size(); ++mi) {
    if (users[mi].empty()) continue;
    const std::vector<GltfPrimitive> prims = read_gltf_mesh(src, int(mi), scene.warnings);
    std::vector<GltfMaterialUse> prim_uses;
    bool emissive = false;
    for (const GltfPrimitive& p : prims) {
      prim_uses.push_back(p.material >= 0 ? uses[size_t(p.material)]
                                          : gltf_default_material(src.file, scene.materials));
      emissive = emissive || prim_uses.back().emission.has_value();
    }
    const std::string mesh_path = "/meshes/" + std::to_string(mi);
    if (users[mi].size() > 1 && emissive)
      scene.warnings.push_back(src.message(
          mesh_path, "emissive mesh used by " + std::to_string(users[mi].size()) +
                         " nodes: copied for each (emissive shapes cannot be instanced)"));
    if (users[mi].size() > 1 && emissive) {
      // Copies cost memory per node: bound them before making them.
      double bytes = 0;
      for (const GltfPrimitive& p : prims)
        bytes += double(p.mesh.positions.size()) * (sizeof(Vec3) * 2 + sizeof(Vec2)) +
                 double(p.mesh.indices.size()) * sizeof(uint32_t);
      check_memory(bytes * double(users[mi].size()),
                   src.file + ":" + mesh_path + ": copies of an emissive mesh");
    }
    if (users[mi].size() == 1 || emissive) {
      for (const auto& [v, t] : users[mi])
        for (size_t j = 0; j < prims.size(); ++j)
          scene.shapes.push_back(
              make_shape(prims[j], prim_uses[j], t, m.nodes[size_t(v->node)].name));
      continue;
    }
    ObjectDesc obj;
    obj.name = "gltf/mesh/" + std::to_string(mi);
    obj.path = mesh_path;
    for (size_t j = 0; j < prims.size(); ++j)
      obj.shapes.push_back(make_shape(prims[j], prim_uses[j], Transform(), m.meshes[mi].name));
    scene.objects.push_back(std::move(obj));
    for (const auto& [v, t] : users[mi])
      scene.instances.push_back(
          {uint32_t(scene.objects.size() - 1), t, v->path, m.nodes[size_t(v->node)].name});
  }
}

}  // namespace

SceneDesc parse_gltf_scene(const std::string& bytes, const std::string& file_name,
                           const std::string& base_dir) {
  check_nesting(json_part(bytes), file_name);
  SceneDesc scene;
  scene.file = file_name;
  const tinygltf::Model model = read_gltf_model(bytes, file_name, base_dir, scene.warnings);
  const GltfSource src{model, file_name};
  warn_unsupported(src, scene.warnings);
  if (!model.asset.generator.empty()) scene.description = "glTF from " + model.asset.generator;
  scene.render.integrator = "path";
  scene.render.width = 640;
  scene.render.height = 480;

  const std::vector<GltfNodeVisit> visits = traverse_gltf_scene(src, scene.warnings);
  map_meshes(src, base_dir, visits, scene);
  map_gltf_lights(src, visits, scene);
  if (!map_gltf_camera(src, visits, scene)) {
    set_default_gltf_camera(scene);
    scene.warnings.push_back(
        src.message("", "no perspective camera: a default camera frames the scene"));
  }
  const auto emits = [](const ShapeDesc& s) { return s.emission.has_value(); };
  if (scene.lights.empty() && std::none_of(scene.shapes.begin(), scene.shapes.end(), emits)) {
    scene.lights.emplace_back(nlohmann::json{{"type", "environment"}, {"radiance", 1.0}}, file_name,
                              "/lights/default");
    scene.warnings.push_back(
        src.message("", "no lights: a constant environment of radiance 1 lights the scene"));
  }
  return scene;
}

SceneDesc load_gltf_scene(const std::string& path) {
  return parse_gltf_scene(read_file_contents(path), path,
                          std::filesystem::path(path).parent_path().string());
}

}  // namespace penumbra
