#include "penumbra/scene/pbrt_materials.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "penumbra/scene/pbrt_shapes.h"
#include "penumbra/scene/pbrt_spectra.h"

namespace penumbra {

namespace {

using nlohmann::json;

// Below this microfacet width both pbrt-v4 and penumbra treat a surface as smooth.
constexpr double kSmoothAlpha = 1e-3;

json rgb_json(Rgb c) {
  return json::array({c.r, c.g, c.b});
}

// The value of a spectrum-valued parameter (rgb, spectrum, blackbody, float, or a texture name):
// a colour array, or a texture object when `allow_texture` (penumbra's textured parameters).
json color_param(const PbrtEntity& e, const std::string& name, const json& fallback,
                 const PbrtTextures& textures, bool allow_texture,
                 std::vector<std::string>& warnings) {
  const PbrtParam* p = e.params.find(name, "rgb spectrum blackbody float texture");
  if (!p) return fallback;
  if (p->type != "texture") return rgb_json(pbrt_color(*p, false, warnings));
  const auto it = textures.find(p->strings.at(0));
  if (it == textures.end()) p->loc.fail("unknown texture \"" + p->strings[0] + "\"");
  const json& v = it->second.value;
  if (v.is_object() && !allow_texture) {
    pbrt_warn(warnings, p->loc,
              "parameter \"" + name + "\" of material \"" + e.type +
                  "\" cannot be textured in penumbra; its default is used");
    return fallback;
  }
  return v;
}

// A float parameter that may name a constant float texture.
double float_param(const PbrtEntity& e, const std::string& name, double fallback,
                   const PbrtTextures& textures, std::vector<std::string>& warnings) {
  const PbrtParam* p = e.params.find(name, "float texture");
  if (!p) return fallback;
  if (p->type == "float") {
    if (p->numbers.size() != 1) p->loc.fail("parameter " + p->declaration() + " takes one value");
    return p->numbers[0];
  }
  const auto it = textures.find(p->strings.at(0));
  if (it == textures.end()) p->loc.fail("unknown texture \"" + p->strings[0] + "\"");
  if (it->second.value.is_number()) return it->second.value.get<double>();
  pbrt_warn(warnings, p->loc,
            "parameter \"" + name + "\" of material \"" + e.type +
                "\" must be a constant in penumbra; its default is used");
  return fallback;
}

// pbrt's roughness parameters as penumbra's roughness (alpha = roughness^2). pbrt-v4: alpha =
// sqrt(roughness) when remaproughness (the default), else roughness itself; anisotropic widths
// become their geometric mean.
double roughness_param(const PbrtEntity& e, const std::string& prefix, const PbrtTextures& tex,
                       std::vector<std::string>& warnings) {
  const double r = float_param(e, prefix + "roughness", 0, tex, warnings);
  const double u = float_param(e, prefix + "uroughness", r, tex, warnings);
  const double v = float_param(e, prefix + "vroughness", r, tex, warnings);
  const bool remap = e.params.get_bool("remaproughness", true);
  if (u < 0 || v < 0) e.loc.fail("roughness must not be negative");
  double au = remap ? std::sqrt(u) : u, av = remap ? std::sqrt(v) : v;
  if (au != av)
    pbrt_warn(warnings, e.loc,
              "anisotropic roughness (uroughness != vroughness) approximated by an isotropic one");
  double alpha = std::sqrt(au * av);
  if (alpha < kSmoothAlpha) return 0.0;
  if (alpha > 1) {
    pbrt_warn(warnings, e.loc, "microfacet width above 1 clamped to 1 (penumbra's largest)");
    alpha = 1;
  }
  return std::sqrt(alpha);
}

// An index of refraction: a float, or a named glass (its d-line index: no dispersion).
double ior_param(const PbrtEntity& e, const PbrtTextures& tex, std::vector<std::string>& warnings) {
  const PbrtParam* p = e.params.find("eta", "float spectrum texture");
  if (!p) return 1.5;
  double ior = 1.5;
  if (p->type == "float" || p->type == "texture") {
    p->used = false;
    ior = float_param(e, "eta", 1.5, tex, warnings);
  } else if (!p->strings.empty()) {
    const auto n = named_glass_ior(p->strings[0]);
    if (!n) p->loc.fail("unknown glass spectrum \"" + p->strings[0] + "\"");
    ior = *n;
    pbrt_warn(warnings, p->loc,
              "\"" + p->strings[0] + "\" taken at 587.6 nm (ior " +
                  std::to_string(ior).substr(0, 6) + "): penumbra renders no dispersion");
  } else {
    ior = pbrt_color(*p, false, warnings).g;
  }
  if (!(ior > 0 && ior < 100)) p->loc.fail("eta must lie in (0, 100)");
  return ior;
}

json conductor(const PbrtEntity& e, const std::string& prefix, const PbrtTextures& tex,
               std::vector<std::string>& warnings) {
  json m = {{"type", "conductor"}, {"roughness", roughness_param(e, prefix, tex, warnings)}};
  if (e.params.has(prefix + "reflectance")) {
    // pbrt-v4 turns a reflectance r into eta = 1, k = 2 sqrt(r) / sqrt(1 - r), whose Fresnel
    // reflectance at normal incidence is exactly r.
    const json r = color_param(e, prefix + "reflectance", json(), tex, false, warnings);
    json k = json::array();
    for (int i = 0; i < 3; ++i) {
      const double c = std::clamp(r.is_array() ? r[i].get<double>() : 0.5, 0.0, 0.9996);
      k.push_back(std::min(100.0, 2 * std::sqrt(c) / std::sqrt(1 - c)));
    }
    m["eta"] = 1.0;
    m["k"] = k;
    return m;
  }
  m["eta"] = color_param(e, prefix + "eta", rgb_json(*named_metal_rgb("metal-Cu-eta")), tex, false,
                         warnings);
  m["k"] =
      color_param(e, prefix + "k", rgb_json(*named_metal_rgb("metal-Cu-k")), tex, false, warnings);
  return m;
}

json dielectric(const PbrtEntity& e, const PbrtTextures& tex, std::vector<std::string>& warnings) {
  const double ior = ior_param(e, tex, warnings);
  const double r = roughness_param(e, "", tex, warnings);
  if (r == 0) return {{"type", "dielectric"}, {"ior", ior}};
  return {{"type", "rough_dielectric"}, {"ior", ior}, {"roughness", r}};
}

// A spectrum `imagemap` as penumbra's image texture (uv mapping, bilinear), or null (with a
// warning) for an image format penumbra does not read.
json image_map(const PbrtEntity& e, const std::vector<std::string>& search_dirs,
               std::vector<std::string>& warnings) {
  const std::string name = e.params.get_string("filename", "");
  if (name.empty()) e.loc.fail("Texture \"imagemap\" needs \"string filename\"");
  const std::string path = pbrt_resolve(name, search_dirs);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) e.loc.fail("image not found: " + path);
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".png" && ext != ".exr" && ext != ".pfm") {
    pbrt_warn(
        warnings, e.loc,
        "imagemap \"" + name + "\": penumbra reads PNG, EXR and PFM images; mid grey is used");
    for (const PbrtParam& p : e.params.all()) p.used = true;
    return nullptr;
  }
  if (e.params.get_string("mapping", "uv") != "uv")
    pbrt_warn(warnings, e.loc, "only the uv mapping is supported; uv is used");
  const std::string filter = e.params.get_string("filter", "bilinear");
  if (filter != "bilinear")
    pbrt_warn(warnings, e.loc, "imagemap filter \"" + filter + "\" is read as bilinear");
  const std::string encoding = e.params.get_string("encoding", ext == ".png" ? "sRGB" : "linear");
  if ((ext == ".png") != (encoding == "sRGB"))
    pbrt_warn(warnings, e.loc,
              "imagemap encoding \"" + encoding +
                  "\" is not supported: PNG is decoded as sRGB, EXR and PFM as linear");
  if (e.params.get_bool("invert", false))
    pbrt_warn(warnings, e.loc, "imagemap \"invert\" is not supported; ignored");
  if (e.params.get_float("scale", 1.0) != 1.0)
    pbrt_warn(warnings, e.loc, "imagemap \"scale\" is not supported; ignored");
  std::string wrap = e.params.get_string("wrap", "repeat");
  if (wrap == "octahedralsphere") {
    pbrt_warn(warnings, e.loc, "imagemap wrap \"octahedralsphere\" is read as \"repeat\"");
    wrap = "repeat";
  } else if (wrap != "repeat" && wrap != "clamp" && wrap != "black") {
    e.loc.fail("unknown imagemap wrap \"" + wrap +
               "\" (pbrt-v4 has: repeat, black, clamp, octahedralsphere)");
  }
  const double su = e.params.get_float("uscale", 1), sv = e.params.get_float("vscale", 1);
  const double du = e.params.get_float("udelta", 0), dv = e.params.get_float("vdelta", 0);
  if (!(su != 0 && sv != 0 && std::isfinite(su) && std::isfinite(sv)))
    e.loc.fail("imagemap uscale and vscale must be finite and non-zero");
  return json{
      {"type", "image"}, {"file", path}, {"scale", {su, sv}}, {"offset", {du, dv}}, {"wrap", wrap}};
}

void mark_used(const PbrtEntity& e, std::initializer_list<const char*> names) {
  for (const PbrtParam& p : e.params.all())
    for (const char* n : names)
      if (p.name == n) p.used = true;
}

}  // namespace

PbrtTexture map_pbrt_texture(const std::string& value_type, const PbrtEntity& e,
                             const PbrtTextures& textures,
                             const std::vector<std::string>& search_dirs,
                             std::vector<std::string>& warnings) {
  PbrtTexture t;
  t.is_float = value_type == "float";
  const json grey = t.is_float ? json(0.5) : json::array({0.5, 0.5, 0.5});
  auto value = [&](const std::string& name, double fallback) -> json {
    if (t.is_float) return float_param(e, name, fallback, textures, warnings);
    json v = color_param(e, name, json::array({fallback, fallback, fallback}), textures, false,
                         warnings);
    return v;
  };
  if (e.type == "constant") {
    t.value = value("value", 1.0);
  } else if (e.type == "checkerboard") {
    if (e.params.get_int("dimension", 2) != 2 || e.params.get_string("mapping", "uv") != "uv")
      pbrt_warn(warnings, e.loc, "only 2D checkerboards with uv mapping are supported");
    if (e.params.get_float("udelta", 0) != 0 || e.params.get_float("vdelta", 0) != 0)
      pbrt_warn(warnings, e.loc, "checkerboard udelta/vdelta offsets are not supported");
    const double su = e.params.get_float("uscale", 1), sv = e.params.get_float("vscale", 1);
    if (!(su > 0 && sv > 0)) e.loc.fail("checkerboard uscale and vscale must be positive");
    t.value = {{"type", "checkerboard"},
               {"scale", {su, sv}},
               {"colors", {value("tex1", 1.0), value("tex2", 0.0)}}};
    if (t.is_float) {
      pbrt_warn(warnings, e.loc, "a float checkerboard is used as its mean value");
      t.value = 0.5 * (t.value["colors"][0].get<double>() + t.value["colors"][1].get<double>());
    }
  } else if (e.type == "imagemap" && !t.is_float) {
    t.value = image_map(e, search_dirs, warnings);
    if (t.value.is_null()) t.value = grey;
  } else if (e.type == "scale") {
    const json v = value("tex", 1.0);
    const double s = float_param(e, "scale", 1, textures, warnings);
    if (v.is_number()) {
      t.value = v.get<double>() * s;
    } else if (v.is_array()) {
      t.value =
          json::array({v[0].get<double>() * s, v[1].get<double>() * s, v[2].get<double>() * s});
    } else {
      pbrt_warn(warnings, e.loc, "a scaled non-constant texture is replaced by mid grey");
      t.value = grey;
    }
  } else {
    pbrt_warn(warnings, e.loc,
              "Texture class \"" + e.type + "\" is not supported; it stands for a mid grey (0.5)");
    for (const PbrtParam& p : e.params.all()) p.used = true;
    t.value = grey;
  }
  return t;
}

std::optional<json> map_pbrt_material(const PbrtEntity& e, const PbrtTextures& tex,
                                      std::vector<std::string>& warnings) {
  if (e.params.find("displacement", "float texture"))
    pbrt_warn(warnings, e.loc, "displacement (bump mapping) is not supported; ignored");
  if (e.params.find("normalmap", "string"))
    pbrt_warn(warnings, e.loc, "normalmap is not supported; ignored");
  const std::string& t = e.type;
  auto nearest = [&](const std::string& what) {
    pbrt_warn(warnings, e.loc, "material \"" + t + "\" rendered as " + what + " (nearest)");
  };
  if (t == "interface" || t == "" || t == "none") {
    pbrt_warn(warnings, e.loc,
              "material \"" + t +
                  "\" marks medium boundaries, not surfaces: shapes with it are not "
                  "imported");
    return std::nullopt;
  }
  if (t == "diffuse")
    return json{{"type", "diffuse"},
                {"albedo", color_param(e, "reflectance", 0.5, tex, true, warnings)}};
  if (t == "conductor") return conductor(e, "", tex, warnings);
  if (t == "dielectric") return dielectric(e, tex, warnings);
  if (t == "thindielectric") {
    nearest("\"dielectric\" (a solid, not a thin sheet)");
    return json{{"type", "dielectric"}, {"ior", ior_param(e, tex, warnings)}};
  }
  if (t == "coateddiffuse") {
    nearest("\"diffuse\" with its reflectance (the glossy coating is dropped)");
    mark_used(e, {"roughness", "uroughness", "vroughness", "remaproughness", "thickness", "eta",
                  "albedo", "g", "maxdepth", "nsamples"});
    return json{{"type", "diffuse"},
                {"albedo", color_param(e, "reflectance", 0.5, tex, true, warnings)}};
  }
  if (t == "coatedconductor") {
    nearest("\"conductor\" with its conductor parameters (the dielectric coating is dropped)");
    mark_used(e, {"interface.roughness", "interface.uroughness", "interface.vroughness",
                  "interface.eta", "thickness", "albedo", "g", "maxdepth", "nsamples"});
    return conductor(e, "conductor.", tex, warnings);
  }
  if (t == "diffusetransmission") {
    nearest("\"diffuse\" with its reflectance (no transmission)");
    mark_used(e, {"transmittance", "scale"});
    return json{{"type", "diffuse"},
                {"albedo", color_param(e, "reflectance", 0.25, tex, true, warnings)}};
  }
  if (t == "measured" || t == "hair" || t == "subsurface") {
    nearest("\"diffuse\" of albedo 0.5");
    for (const PbrtParam& p : e.params.all()) p.used = true;
    return json{{"type", "diffuse"}, {"albedo", 0.5}};
  }
  e.loc.fail("unknown material \"" + t +
             "\" (pbrt-v4 has: coateddiffuse, coatedconductor, conductor, dielectric, diffuse, "
             "diffusetransmission, hair, interface, measured, mix, subsurface, thindielectric)");
}

}  // namespace penumbra
