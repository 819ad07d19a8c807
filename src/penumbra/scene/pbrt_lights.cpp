#include "penumbra/scene/pbrt_lights.h"

#include <cmath>
#include <filesystem>
#include <numbers>

#include "penumbra/scene/pbrt_shapes.h"
#include "penumbra/scene/pbrt_spectra.h"
#include "penumbra/scene/transform_parser.h"

namespace penumbra {

namespace {

using nlohmann::json;

json rgb_json(Rgb c) {
  return json::array({c.r, c.g, c.b});
}
json vec_json(Vec3 v) {
  return json::array({v.x, v.y, v.z});
}

// Luminance of linear sRGB (Rec. 709 weights).
double luminance(Rgb c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

// The spectrum parameter `name` as RGB (white when absent), times "scale". pbrt-v4 normalises an
// RGB or blackbody light spectrum to its luminance and renders "rgb L [1 1 1]" as (1, 1, 1) in
// linear sRGB, so an rgb value is taken as it is.
Rgb emitted(const PbrtEntity& e, const std::string& name, std::vector<std::string>& warnings) {
  const PbrtParam* p = e.params.find(name, "rgb spectrum blackbody");
  const Rgb c = p ? pbrt_color(*p, true, warnings) : Rgb(1.0f);
  const double s = e.params.get_float("scale", 1.0);
  return c * float(s);
}

// `c` rescaled to luminance `target` (pbrt's "power", "illuminance"), when that is given (> 0).
Rgb photometric(const PbrtEntity& e, Rgb c, const char* param, double per_unit) {
  const double target = e.params.get_float(param, -1);
  if (!(target > 0)) return c;
  const double y = luminance(c);
  if (!(y > 0)) e.loc.fail(std::string("\"") + param + "\" needs a light with a non-black colour");
  return c * float(target / (per_unit * y));
}

// The rotation (or mirrored rotation) of `to_world` as 16 row-major numbers: translation dropped,
// a uniform scale divided out; anything else is refused at the light.
json rotation_json(const PbrtEntity& e, const Transform& to_world) {
  const auto& m = to_world.matrix().m;
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  const double s = std::cbrt(std::fabs(det));
  if (!(s > 0) || !is_similarity(to_world))
    e.loc.fail("infinite light with a map: its transform must be a rotation (it scales or shears)");
  json a = json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) a.push_back(r < 3 && c < 3 ? m[r][c] / s : (r == c ? 1.0 : 0.0));
  return a;
}

// pbrt-v4's spot light (lights.cpp, SpotLight::Create): "I" * "scale" at "from", aimed at "to",
// "coneangle" (30) and "conedeltaangle" (5) in degrees; with "power" P the intensity's luminance
// becomes P / k_e, k_e = 2 pi ((1 - cos_start) + (cos_start - cos_end) / 2) the solid angle that
// the falloff covers (cos_end = cos(coneangle), cos_start = cos(coneangle - conedeltaangle)).
json map_spot(const PbrtEntity& e, const Transform& to_world, std::vector<std::string>& warnings) {
  const double angle = e.params.get_float("coneangle", 30.0);
  const double delta = e.params.get_float("conedeltaangle", 5.0);
  if (!(angle > 0 && angle <= 180))
    e.loc.fail("spot light: \"coneangle\" must be in (0, 180] degrees");
  if (!(delta >= 0 && delta <= angle))
    e.loc.fail("spot light: \"conedeltaangle\" must be in [0, coneangle] degrees");
  const double cos_end = std::cos(angle * std::numbers::pi / 180);
  const double cos_start = std::cos((angle - delta) * std::numbers::pi / 180);
  const double k_e = 2 * std::numbers::pi * ((1 - cos_start) + (cos_start - cos_end) / 2);
  const Rgb i = photometric(e, emitted(e, "I", warnings), "power", k_e);
  const Vec3 from = e.params.get_vec3("from").value_or(Vec3(0.0f));
  const Vec3 to = e.params.get_vec3("to").value_or(Vec3(0, 0, 1));
  const Vec3 d = to_world.vector(to - from);
  if (!(length(d) > 0)) e.loc.fail("spot light: \"from\" and \"to\" coincide");
  return json{{"type", "spot"},           {"position", vec_json(to_world.point(from))},
              {"direction", vec_json(d)}, {"intensity", rgb_json(i)},
              {"cone_angle", angle},      {"cone_delta", delta}};
}

}  // namespace

std::optional<json> map_pbrt_light(const PbrtEntity& e, const Transform& to_world,
                                   const std::vector<std::string>& search_dirs,
                                   std::vector<std::string>& warnings) {
  const std::string& t = e.type;
  if (t == "point") {
    Rgb i = photometric(e, emitted(e, "I", warnings), "power", 4 * std::numbers::pi);
    const Vec3 from = e.params.get_vec3("from").value_or(Vec3(0.0f));
    return json{{"type", "point"},
                {"position", vec_json(to_world.point(from))},
                {"intensity", rgb_json(i)}};
  }
  if (t == "distant") {
    Rgb l = photometric(e, emitted(e, "L", warnings), "illuminance", 1.0);
    const Vec3 from = e.params.get_vec3("from").value_or(Vec3(0.0f));
    const Vec3 to = e.params.get_vec3("to").value_or(Vec3(0, 0, 1));
    const Vec3 d = to_world.vector(to - from);
    if (!(length(d) > 0)) e.loc.fail("distant light: \"from\" and \"to\" coincide");
    return json{{"type", "directional"}, {"direction", vec_json(d)}, {"irradiance", rgb_json(l)}};
  }
  if (t == "infinite") {
    const std::string file = e.params.get_string("filename", "");
    e.params.find("portal", "point3");
    if (file.empty()) {
      // Illuminance E of an upward surface under a constant sky of radiance L: E = pi L.
      const Rgb l = photometric(e, emitted(e, "L", warnings), "illuminance", std::numbers::pi);
      return json{{"type", "environment"}, {"radiance", rgb_json(l)}};
    }
    if (e.params.has("L")) e.loc.fail("infinite light: give either \"L\" or \"filename\"");
    if (e.params.find("illuminance", "float"))
      pbrt_warn(warnings, e.loc,
                "infinite light \"illuminance\" with an image is not supported; \"scale\" is used");
    // pbrt-v4's image maps are equal-area octahedral squares in the light's frame (+z at the
    // centre); the light's rotation (with the world mirror) becomes the map-to-world transform.
    const std::string path = pbrt_resolve(file, search_dirs);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      e.loc.fail("infinite light map not found: " + path);
    return json{{"type", "environment"},
                {"radiance", rgb_json(Rgb(float(e.params.get_float("scale", 1.0))))},
                {"map", path},
                {"mapping", "octahedral"},
                {"transform", json::array({json{{"matrix", rotation_json(e, to_world)}}})}};
  }
  if (t == "spot") return map_spot(e, to_world, warnings);
  if (t == "goniometric" || t == "projection") {
    pbrt_warn(warnings, e.loc, "LightSource \"" + t + "\" is not supported by penumbra; skipped");
    for (const PbrtParam& p : e.params.all()) p.used = true;
    return std::nullopt;
  }
  e.loc.fail("unknown LightSource \"" + t +
             "\" (pbrt-v4 has: distant, goniometric, infinite, point, projection, spot)");
}

PbrtAreaLight map_pbrt_area_light(const PbrtEntity& e, std::vector<std::string>& warnings) {
  if (e.type != "diffuse")
    e.loc.fail("unknown AreaLightSource \"" + e.type + "\" (pbrt-v4 has: diffuse)");
  PbrtAreaLight a;
  a.radiance = emitted(e, "L", warnings);
  if (a.radiance.r < 0 || a.radiance.g < 0 || a.radiance.b < 0)
    e.loc.fail("area light radiance L * scale must not be negative");
  a.two_sided = e.params.get_bool("twosided", false);
  if (e.params.find("filename", "string"))
    pbrt_warn(warnings, e.loc, "image area lights (\"filename\") are not supported; L is used");
  if (e.params.find("power", "float"))
    pbrt_warn(warnings, e.loc, "area light \"power\" is not supported; L and scale are used");
  return a;
}

}  // namespace penumbra
