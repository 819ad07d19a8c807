#include "penumbra/scene/scene_loader.h"

#include <cctype>
#include <climits>
#include <filesystem>
#include <set>
#include <utility>

#include "penumbra/scene/gltf_loader.h"
#include "penumbra/scene/json_value.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/object_parser.h"
#include "penumbra/scene/pbrt_parser.h"
#include "penumbra/scene/shape_parser.h"

namespace penumbra {

using nlohmann::json;

namespace {

constexpr int64_t kMaxResolution = 65536;

// A non-empty string (integrator and accelerator names; their registries check them).
std::string parse_name(const json& v, const JsonPlace& place) {
  std::string s = json_string(v, place);
  if (s.empty()) place.fail("must not be empty");
  return s;
}

RenderSettings parse_render(const json& v, const JsonPlace& place) {
  if (!v.is_object()) place.fail("expected an object");
  json_check_keys(v, place,
                  {"resolution", "spp", "max_depth", "seed", "integrator", "accel", "sampler",
                   "filter", "background"},
                  "the render section");
  RenderSettings r;
  if (const json* res = json_find(v, "resolution")) {
    const JsonPlace at = place.key("resolution");
    if (!res->is_array() || res->size() != 2)
      at.fail("expected an array of 2 integers [width, height]");
    r.width = static_cast<int>(json_int((*res)[0], at.index(0), 1, kMaxResolution));
    r.height = static_cast<int>(json_int((*res)[1], at.index(1), 1, kMaxResolution));
  }
  if (const json* spp = json_find(v, "spp"))
    r.spp = static_cast<int>(json_int(*spp, place.key("spp"), 1, INT_MAX));
  if (const json* depth = json_find(v, "max_depth"))
    r.max_depth = static_cast<int>(json_int(*depth, place.key("max_depth"), 0, INT_MAX));
  if (const json* seed = json_find(v, "seed")) r.seed = json_uint64(*seed, place.key("seed"));
  if (const json* name = json_find(v, "integrator"))
    r.integrator = parse_name(*name, place.key("integrator"));
  if (const json* name = json_find(v, "accel")) r.accel = parse_name(*name, place.key("accel"));
  if (const json* name = json_find(v, "sampler"))
    r.sampler = parse_name(*name, place.key("sampler"));
  if (const json* name = json_find(v, "filter")) r.filter = parse_name(*name, place.key("filter"));
  if (const json* bg = json_find(v, "background"))
    r.background = json_radiance(*bg, place.key("background"));
  return r;
}

// The file name `v` (a JSON string) resolved against `base_dir` unless absolute or empty.
void resolve_file(json& v, const std::string& base_dir) {
  const std::filesystem::path f(v.get<std::string>());
  if (!f.empty() && f.is_relative() && !base_dir.empty())
    v = (std::filesystem::path(base_dir) / f).lexically_normal().string();
}

// The "file" of every image texture inside a material (a value {"type": "image", "file": ...} at
// any depth), resolved relative to `base_dir` unless absolute.
void resolve_texture_files(json& v, const std::string& base_dir, int depth = 0) {
  if (depth > 64 || base_dir.empty()) return;
  if (v.is_object()) {
    const auto type = v.find("type"), file = v.find("file");
    if (type != v.end() && *type == "image" && file != v.end() && file->is_string())
      resolve_file(*file, base_dir);
    for (auto& [key, child] : v.items()) resolve_texture_files(child, base_dir, depth + 1);
  } else if (v.is_array()) {
    for (auto& child : v) resolve_texture_files(child, base_dir, depth + 1);
  }
}

// Materials: an object from names to {"type": ..., parameters}. Duplicate names are duplicate
// keys, which parse_json already rejects.
std::vector<MaterialDesc> parse_materials(json& v, const JsonPlace& place,
                                          const std::string& base_dir) {
  if (!v.is_object()) place.fail("expected an object mapping material names to materials");
  std::vector<MaterialDesc> out;
  for (auto& [name, params] : v.items()) {
    const JsonPlace at = place.key(name);
    if (name.empty()) at.fail("material name must not be empty");
    resolve_texture_files(params, base_dir);
    out.push_back({name, SceneParams(std::move(params), at.file, at.path)});
  }
  return out;
}

// Lights: an array of {"type": ..., parameters}. The parameters that name files ("map", "file")
// are resolved here relative to `base_dir` (the scene file's folder) unless absolute, as shapes'
// mesh files are, so that a light reads them wherever the program runs; the light checks them.
std::vector<SceneParams> parse_lights(json& v, const JsonPlace& place,
                                      const std::string& base_dir) {
  json_array(v, place);
  std::vector<SceneParams> out;
  for (size_t i = 0; i < v.size(); ++i) {
    const JsonPlace at = place.index(i);
    for (const char* key : {"map", "file"}) {
      if (v[i].is_object() && v[i].contains(key) && v[i][key].is_string())
        resolve_file(v[i][key], base_dir);
    }
    out.emplace_back(std::move(v[i]), at.file, at.path);
  }
  return out;
}

}  // namespace

SceneDesc parse_scene(const std::string& json_text, const std::string& file_name,
                      const std::string& base_dir) {
  json root = parse_json(json_text, file_name);
  const JsonPlace place{file_name, ""};
  if (!root.is_object()) place.fail("expected a JSON object at the top level");
  json_check_keys(root, place,
                  {"description", "camera", "render", "materials", "lights", "objects", "shapes"},
                  "the top level");

  SceneDesc scene;
  scene.file = file_name;
  if (const json* d = json_find(root, "description"))
    scene.description = json_string(*d, place.key("description"));
  json_require(root, place, "camera");
  scene.camera = SceneParams(std::move(root["camera"]), file_name, "/camera");
  if (const json* r = json_find(root, "render"))
    scene.render = parse_render(*r, place.key("render"));
  if (json_find(root, "materials"))
    scene.materials = parse_materials(root["materials"], place.key("materials"), base_dir);
  if (json_find(root, "lights"))
    scene.lights = parse_lights(root["lights"], place.key("lights"), base_dir);

  std::set<std::string> material_names;
  for (const MaterialDesc& m : scene.materials) material_names.insert(m.name);
  if (const json* objects = json_find(root, "objects"))
    scene.objects =
        parse_objects(*objects, place.key("objects"), material_names, base_dir, scene.warnings);
  const JsonPlace shapes_place = place.key("shapes");
  const json& shapes = json_array(json_require(root, place, "shapes"), shapes_place);
  scene.shapes.reserve(shapes.size());
  for (size_t i = 0; i < shapes.size(); ++i) {
    if (is_instance_entry(shapes[i]))
      scene.instances.push_back(parse_instance(shapes[i], shapes_place.index(i), scene.objects));
    else
      scene.shapes.push_back(
          parse_shape(shapes[i], shapes_place.index(i), material_names, base_dir, scene.warnings));
  }
  return scene;
}

SceneDesc load_scene(const std::string& path) {
  // pbrt-v4 and glTF 2.0 scene files by their extension (any case); JSON for everything else.
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".pbrt") return load_pbrt_scene(path);
  if (ext == ".gltf" || ext == ".glb") return load_gltf_scene(path);
  const std::string text = read_file_contents(path);
  return parse_scene(text, path, std::filesystem::path(path).parent_path().string());
}

}  // namespace penumbra
