#include "penumbra/scene/scene_writer.h"

#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "penumbra/scene/ply_writer.h"

namespace penumbra {

using nlohmann::json;

namespace {

json vec3(Vec3 v) {
  return json::array({v.x, v.y, v.z});
}

json rgb(Rgb c) {
  return json::array({c.r, c.g, c.b});
}

// `v` with every string under the keys "map" and "file" (environment maps, image textures, at
// any depth) made absolute, so that the written scene finds them wherever it is written, except
// the names of embedded images, which become their written files (`embedded`: name -> path
// relative to the scene file).
json with_absolute_files(json v, const std::map<std::string, std::string>& embedded,
                         int depth = 0) {
  if (depth > 64) return v;
  if (v.is_object()) {
    for (auto& [key, child] : v.items()) {
      if ((key == "map" || key == "file") && child.is_string() &&
          !child.get<std::string>().empty()) {
        const auto it = embedded.find(child.get<std::string>());
        child =
            it != embedded.end()
                ? it->second
                : std::filesystem::absolute(child.get<std::string>()).lexically_normal().string();
      } else {
        child = with_absolute_files(std::move(child), embedded, depth + 1);
      }
    }
  } else if (v.is_array()) {
    for (auto& child : v) child = with_absolute_files(std::move(child), embedded, depth + 1);
  }
  return v;
}

// A transform as one {"matrix": [16 numbers, row-major]} operation.
json matrix(const Transform& t) {
  json a = json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) a.push_back(t.matrix().m[r][c]);
  return json::array({json{{"matrix", a}}});
}

bool is_identity(const Transform& t) {
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      if (t.matrix().m[r][c] != (r == c ? 1.0 : 0.0)) return false;
  return true;
}

json render_json(const RenderSettings& r) {
  json j = {{"resolution", {r.width, r.height}},
            {"spp", r.spp},
            {"seed", r.seed},
            {"integrator", r.integrator},
            {"accel", r.accel},
            {"sampler", r.sampler},
            {"filter", r.filter},
            {"background", rgb(r.background)}};
  if (r.max_depth) j["max_depth"] = *r.max_depth;
  return j;
}

// The shape record; a triangle mesh goes to `files` as PLY at `mesh_path`.
json shape_json(const ShapeDesc& s, const std::string& mesh_path, std::vector<SceneFile>& files) {
  json j;
  if (const auto* sphere = std::get_if<SphereData>(&s.geometry)) {
    j = {{"type", "sphere"}, {"center", vec3(sphere->center)}, {"radius", sphere->radius}};
  } else if (const auto* quad = std::get_if<QuadData>(&s.geometry)) {
    j = {{"type", "quad"},
         {"origin", vec3(quad->p)},
         {"edge1", vec3(quad->e1)},
         {"edge2", vec3(quad->e2)}};
  } else {
    files.push_back({mesh_path, encode_ply(std::get<TriangleMesh>(s.geometry))});
    j = {{"type", "ply"}, {"file", mesh_path}};
  }
  j["material"] = s.material;
  if (!s.name.empty()) j["name"] = s.name;
  if (s.emission) {
    j["emission"] = rgb(*s.emission);
    if (s.two_sided_emission) j["two_sided"] = true;
  }
  if (!is_identity(s.to_world)) j["transform"] = matrix(s.to_world);
  if (s.to_world_end) j["transform_end"] = matrix(*s.to_world_end);
  return j;
}

}  // namespace

std::vector<SceneFile> write_scene_json(const SceneDesc& scene, const std::string& json_name,
                                        const std::string& mesh_dir) {
  std::vector<SceneFile> files(1);
  const std::string dir = mesh_dir.empty() ? "" : mesh_dir + "/";
  json root;
  root["description"] =
      scene.description.empty() ? "converted by penumbra from " + scene.file : scene.description;
  root["camera"] = scene.camera.json();
  root["render"] = render_json(scene.render);
  // Embedded images as files: dir/image-N.png or .jpg, their bytes as they were.
  std::map<std::string, std::string> embedded;
  for (size_t i = 0; i < scene.images.size(); ++i) {
    const EmbeddedImage& image = scene.images[i];
    const std::string path =
        dir + "image-" + std::to_string(i) + (image.mime_type == "image/jpeg" ? ".jpg" : ".png");
    embedded[image.name] = path;
    files.push_back({path, image.bytes ? *image.bytes : std::string()});
  }
  json materials = json::object();
  for (const MaterialDesc& m : scene.materials)
    materials[m.name] = with_absolute_files(m.params.json(), embedded);
  root["materials"] = materials;
  json lights = json::array();
  for (const SceneParams& l : scene.lights)
    lights.push_back(with_absolute_files(l.json(), embedded));
  root["lights"] = lights;
  if (!scene.objects.empty()) {
    json objects = json::object();
    for (size_t o = 0; o < scene.objects.size(); ++o) {
      json shapes = json::array();
      const ObjectDesc& object = scene.objects[o];
      for (size_t i = 0; i < object.shapes.size(); ++i)
        shapes.push_back(shape_json(
            object.shapes[i],
            dir + "object-" + std::to_string(o) + "-" + std::to_string(i) + ".ply", files));
      objects[object.name] = json{{"shapes", shapes}};
    }
    root["objects"] = objects;
  }
  json shapes = json::array();
  for (size_t i = 0; i < scene.shapes.size(); ++i)
    shapes.push_back(
        shape_json(scene.shapes[i], dir + "shape-" + std::to_string(i) + ".ply", files));
  for (const InstanceDesc& inst : scene.instances) {
    json j = {{"type", "instance"}, {"object", scene.objects.at(inst.object).name}};
    if (!inst.name.empty()) j["name"] = inst.name;
    if (!is_identity(inst.to_world)) j["transform"] = matrix(inst.to_world);
    shapes.push_back(j);
  }
  root["shapes"] = shapes;
  files[0] = {json_name, root.dump(2) + "\n"};
  return files;
}

}  // namespace penumbra
