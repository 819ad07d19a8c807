#include "penumbra/scene/gltf_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace penumbra {

using nlohmann::json;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kDefaultWidth = 640;

struct D3 {
  double x, y, z;
};

D3 apply(const Mat4& m, D3 v, double w) {
  const auto& a = m.m;
  return {a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z + a[0][3] * w,
          a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z + a[1][3] * w,
          a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z + a[2][3] * w};
}

double norm(D3 v) {
  return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}

json to_json(D3 v) {
  return json::array({v.x, v.y, v.z});
}

// The unit direction `v`, or an error at `path` when the node's transform collapses it.
D3 unit(const GltfSource& src, D3 v, const std::string& path) {
  const double len = norm(v);
  if (!(len > 1e-12) || !std::isfinite(len))
    src.fail(path, "the node's transform collapses the view or light direction");
  return {v.x / len, v.y / len, v.z / len};
}

Rgb light_color(const GltfSource& src, const tinygltf::Light& l, const std::string& at) {
  Rgb c(1.0f);
  if (l.color.size() == 3) c = Rgb(float(l.color[0]), float(l.color[1]), float(l.color[2]));
  const Rgb out = c * float(l.intensity);
  for (int i = 0; i < 3; ++i)
    if (!(std::isfinite(out[i]) && out[i] >= 0.0f))
      src.fail(at, "color times intensity must be finite and non-negative");
  return out;
}

}  // namespace

bool map_gltf_camera(const GltfSource& src, const std::vector<GltfNodeVisit>& visits,
                     SceneDesc& scene) {
  const auto& cameras = src.model.cameras;
  for (const GltfNodeVisit& v : visits) {
    const int c = src.model.nodes[size_t(v.node)].camera;
    if (c < 0) continue;
    if (size_t(c) >= cameras.size())
      src.fail(v.path + "/camera", "camera " + std::to_string(c) + " out of range (" +
                                       std::to_string(cameras.size()) + " cameras)");
    const std::string at = "/cameras/" + std::to_string(c);
    const tinygltf::Camera& cam = cameras[size_t(c)];
    if (cam.type != "perspective") {
      scene.warnings.push_back(
          src.message(at, "camera type \"" + cam.type + "\" not supported: using the default"));
      return false;
    }
    const double yfov = cam.perspective.yfov;
    if (!(yfov > 0.0 && yfov < kPi)) src.fail(at + "/perspective/yfov", "must lie in (0, pi)");
    // glTF cameras look down their local -z with +y up.
    const D3 eye = apply(v.world, {0, 0, 0}, 1);
    const D3 fwd = unit(src, apply(v.world, {0, 0, -1}, 0), v.path);
    const D3 up = unit(src, apply(v.world, {0, 1, 0}, 0), v.path);
    scene.camera =
        SceneParams(json{{"type", "pinhole"},
                         {"position", to_json(eye)},
                         {"look_at", to_json({eye.x + fwd.x, eye.y + fwd.y, eye.z + fwd.z})},
                         {"up", to_json(up)},
                         {"vfov", yfov * 180.0 / kPi}},
                    src.file, at);
    const double aspect = cam.perspective.aspectRatio;
    if (aspect > 0.0 && std::isfinite(aspect)) {
      scene.render.width = kDefaultWidth;
      // Clamped before the conversion: an aspect ratio of 1e-9 must not overflow an int.
      scene.render.height = int(std::lround(std::clamp(kDefaultWidth / aspect, 1.0, 65536.0)));
    }
    return true;
  }
  return false;
}

void map_gltf_lights(const GltfSource& src, const std::vector<GltfNodeVisit>& visits,
                     SceneDesc& scene) {
  const auto& lights = src.model.lights;
  for (const GltfNodeVisit& v : visits) {
    const auto& ext = src.model.nodes[size_t(v.node)].extensions;
    const auto it = ext.find("KHR_lights_punctual");
    if (it == ext.end()) continue;
    const std::string ref = v.path + "/extensions/KHR_lights_punctual/light";
    if (!it->second.IsObject() || !it->second.Has("light") || !it->second.Get("light").IsNumber())
      src.fail(ref, "expected a light index");
    const double index = it->second.Get("light").GetNumberAsDouble();
    if (!(index >= 0 && index < double(lights.size())) || index != std::floor(index))
      src.fail(ref, "light " + std::to_string(index) + " out of range (" +
                        std::to_string(lights.size()) + " lights)");
    const std::string at = "/extensions/KHR_lights_punctual/lights/" + std::to_string(int(index));
    const tinygltf::Light& l = lights[size_t(index)];
    const Rgb c = light_color(src, l, at);
    if (l.range > 0.0)
      scene.warnings.push_back(src.message(at + "/range", "range ignored (no cut-off)"));
    json p;
    if (l.type == "point") {
      p = {{"type", "point"},
           {"position", to_json(apply(v.world, {0, 0, 0}, 1))},
           {"intensity", json::array({c.r, c.g, c.b})}};
    } else if (l.type == "spot") {
      // A cone about the node's -z; the spec asks 0 <= inner < outer <= pi/2 and leaves the
      // falloff between them to the renderer: penumbra's (pbrt-v4's) smoothstep in cos.
      const double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
      if (!(inner >= 0 && inner < outer && outer <= std::numbers::pi / 2 + 1e-9))
        src.fail(at + "/spot",
                 "cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
      const double deg = 180.0 / std::numbers::pi;
      p = {{"type", "spot"},
           {"position", to_json(apply(v.world, {0, 0, 0}, 1))},
           {"direction", to_json(unit(src, apply(v.world, {0, 0, -1}, 0), v.path))},
           {"intensity", json::array({c.r, c.g, c.b})},
           {"cone_angle", std::min(outer * deg, 90.0)},
           {"cone_delta", std::min(outer * deg, 90.0) - inner * deg}};
    } else if (l.type == "directional") {
      p = {{"type", "directional"},
           {"direction", to_json(unit(src, apply(v.world, {0, 0, -1}, 0), v.path))},
           {"irradiance", json::array({c.r, c.g, c.b})}};
    } else {
      src.fail(at + "/type", "unknown light type \"" + l.type + "\"");
    }
    scene.lights.emplace_back(std::move(p), src.file, at);
  }
}

void set_default_gltf_camera(SceneDesc& scene) {
  // The bounds of every vertex in world space (shapes and instanced objects).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  D3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
  auto add = [&](const Transform& t, const ShapeDesc& s) {
    if (const auto* mesh = std::get_if<TriangleMesh>(&s.geometry))
      for (const Vec3& p : mesh->positions) {
        const Vec3 w = t.point(s.to_world.point(p));
        lo = {std::min(lo.x, double(w.x)), std::min(lo.y, double(w.y)),
              std::min(lo.z, double(w.z))};
        hi = {std::max(hi.x, double(w.x)), std::max(hi.y, double(w.y)),
              std::max(hi.z, double(w.z))};
      }
  };
  for (const ShapeDesc& s : scene.shapes) add(Transform(), s);
  for (const InstanceDesc& inst : scene.instances)
    for (const ShapeDesc& s : scene.objects[inst.object].shapes) add(inst.to_world, s);
  D3 centre{0, 0, 0};
  double radius = 1.0;
  if (lo.x <= hi.x) {
    centre = {(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2};
    radius = norm(D3{hi.x - centre.x, hi.y - centre.y, hi.z - centre.z});
    if (!(radius > 0.0)) radius = 1.0;
  }
  // From +z and 15 degrees above, at the distance where the sphere's silhouette fills the vfov.
  const double vfov = 40.0;
  const double dist = radius / std::sin(vfov / 2 * kPi / 180.0);
  const double elev = 15.0 * kPi / 180.0;
  const D3 eye{centre.x, centre.y + dist * std::sin(elev), centre.z + dist * std::cos(elev)};
  scene.camera = SceneParams(json{{"type", "pinhole"},
                                  {"position", to_json(eye)},
                                  {"look_at", to_json(centre)},
                                  {"up", json::array({0, 1, 0})},
                                  {"vfov", vfov}},
                             scene.file, "/cameras");
}

}  // namespace penumbra
