#include "penumbra/scene/pbrt_parser.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <set>

#include "penumbra/core/error.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/pbrt_lights.h"
#include "penumbra/scene/pbrt_materials.h"
#include "penumbra/scene/pbrt_options.h"
#include "penumbra/scene/pbrt_shapes.h"
#include "penumbra/scene/pbrt_tokenizer.h"
#include "penumbra/scene/pbrt_transforms.h"

namespace penumbra {

namespace {

using Kind = PbrtToken::Kind;
namespace fs = std::filesystem;

constexpr int kMaxIncludeDepth = 64;
constexpr const char* kDefaultMaterial = "pbrt-default";

/// What AttributeBegin saves and AttributeEnd restores.
struct GraphicsState {
  Transform ctm;
  bool reverse_orientation = false;
  std::string material;  ///< name of a MaterialDesc; "" for pbrt's default (diffuse 0.5)
  std::optional<PbrtAreaLight> area_light;
};

/// A saved state: by AttributeBegin (everything) or TransformBegin (the CTM only).
struct SavedState {
  GraphicsState state;
  bool transform_only;
  PbrtLoc loc;
};

/// An open file: its tokens and directory.
struct Source {
  std::unique_ptr<PbrtTokenizer> tokens;
  std::string dir;
};

class PbrtParser {
 public:
  PbrtParser(const std::string& file, const std::string& base_dir) : base_dir_(base_dir) {
    scene_.file = file;
  }
  SceneDesc run(std::string text, const std::string& file);

 private:
  PbrtTokenizer& tok() { return *sources_.back().tokens; }
  std::vector<std::string>& warnings() { return scene_.warnings; }
  void directive(const PbrtToken& t);
  void include(const PbrtToken& t);
  bool transform_directive(const PbrtToken& t);
  void option_directive(const PbrtToken& t, std::optional<PbrtEntity>& slot);
  void world_begin(const PbrtToken& t);
  void attribute_end(const PbrtToken& t, bool transform_only);
  void shape(const PbrtToken& t);
  void material(const PbrtToken& t);
  void make_named_material(const PbrtToken& t);
  void texture(const PbrtToken& t);
  void light(const PbrtToken& t);
  std::string default_material();
  void add_material(const std::string& name, PbrtEntity e);
  void finish();
  void require_world(const PbrtToken& t, bool world);

  std::string string_arg(const PbrtToken& directive);
  PbrtEntity entity(const PbrtToken& directive) {
    PbrtEntity e;
    e.type = string_arg(directive);
    e.loc = directive.loc;
    e.params = PbrtParams::parse(tok());
    return e;
  }
  std::vector<double> numbers(const PbrtToken& directive, size_t n);

  SceneDesc scene_;
  std::string base_dir_;
  std::vector<Source> sources_;
  GraphicsState gs_;
  std::vector<SavedState> stack_;
  std::map<std::string, Transform> named_;  ///< named coordinate systems
  PbrtOptions options_;
  bool in_world_ = false;
  Transform world_from_pbrt_;      ///< the mirror x -> -x, or the identity (set at WorldBegin)
  std::optional<PbrtLoc> object_;  ///< inside ObjectBegin ... ObjectEnd
  std::map<std::string, size_t> materials_;    ///< name -> index in scene_.materials
  std::map<std::string, PbrtLoc> referenced_;  ///< NamedMaterial names -> first use
  std::map<std::string, nlohmann::json> material_json_;
  PbrtTextures textures_;
  int anonymous_ = 0;
};

std::string PbrtParser::string_arg(const PbrtToken& directive) {
  const PbrtToken t = tok().next();
  if (t.kind != Kind::kString)
    t.loc.fail(directive.text + " expects a quoted string, got " + t.describe());
  return t.text;
}

std::vector<double> PbrtParser::numbers(const PbrtToken& directive, size_t n) {
  // n numbers, bare or in one bracketed list.
  const bool bracketed = tok().peek().kind == Kind::kOpen;
  const PbrtToken open = bracketed ? tok().next() : PbrtToken{};
  std::vector<double> v;
  while (v.size() < n) {
    const PbrtToken t = tok().next();
    if (t.kind == Kind::kClose && bracketed)
      t.loc.fail(directive.text + " takes " + std::to_string(n) + " numbers, got " +
                 std::to_string(v.size()));
    if (t.kind == Kind::kEnd && bracketed)
      open.loc.fail("unbalanced '[': no matching ']' before the end of the file");
    double x;
    if (t.kind != Kind::kWord || !pbrt_parse_number(t.text, x))
      t.loc.fail(directive.text + " takes " + std::to_string(n) + " numbers, got " + t.describe());
    v.push_back(x);
  }
  if (bracketed) {
    const PbrtToken t = tok().next();
    if (t.kind == Kind::kEnd)
      open.loc.fail("unbalanced '[': no matching ']' before the end of the file");
    if (t.kind != Kind::kClose)
      t.loc.fail(directive.text + " takes " + std::to_string(n) + " numbers; expected ']', got " +
                 t.describe());
  }
  return v;
}

void PbrtParser::require_world(const PbrtToken& t, bool world) {
  if (world && !in_world_) t.loc.fail(t.text + " is only allowed after WorldBegin");
  if (!world && in_world_) t.loc.fail(t.text + " is not allowed after WorldBegin");
}

SceneDesc PbrtParser::run(std::string text, const std::string& file) {
  sources_.push_back({std::make_unique<PbrtTokenizer>(std::move(text), file), base_dir_});
  while (!sources_.empty()) {
    const PbrtToken t = tok().next();
    if (t.kind == Kind::kEnd) {
      sources_.pop_back();
      continue;
    }
    if (t.kind == Kind::kClose) t.loc.fail("unbalanced ']' outside a parameter list");
    if (t.kind != Kind::kWord) t.loc.fail("expected a directive, got " + t.describe());
    directive(t);
  }
  finish();
  return std::move(scene_);
}

void PbrtParser::include(const PbrtToken& t) {
  const std::string name = string_arg(t);
  if (sources_.size() >= size_t(kMaxIncludeDepth))
    t.loc.fail(t.text + " nested more than " + std::to_string(kMaxIncludeDepth) +
               " deep (does a file include itself?)");
  const std::string path = pbrt_resolve(name, {sources_.back().dir, base_dir_});
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) t.loc.fail(t.text + " file not found: " + path);
  if (path.size() > 3 && path.ends_with(".gz"))
    t.loc.fail(t.text + " of a gzip-compressed file is not supported: " + path);
  sources_.push_back({std::make_unique<PbrtTokenizer>(read_file_contents(path), path),
                      fs::path(path).parent_path().string()});
}

void PbrtParser::directive(const PbrtToken& t) {
  const std::string& d = t.text;
  if (transform_directive(t)) return;
  if (d == "Include" || d == "Import") return include(t);
  if (d == "AttributeBegin" || d == "TransformBegin") {
    if (d == "TransformBegin")
      pbrt_warn(warnings(), t.loc, "TransformBegin is deprecated in pbrt-v4 (read as in pbrt-v3)");
    stack_.push_back({gs_, d == "TransformBegin", t.loc});
    return;
  }
  if (d == "AttributeEnd") return attribute_end(t, false);
  if (d == "TransformEnd") return attribute_end(t, true);
  if (d == "ReverseOrientation") {
    gs_.reverse_orientation = !gs_.reverse_orientation;
    return;
  }
  if (d == "Camera") {
    require_world(t, false);
    option_directive(t, options_.camera);
    // The CTM here is camera-from-world; pbrt names its inverse "camera".
    options_.camera_to_world = gs_.ctm.inverted();
    named_["camera"] = options_.camera_to_world;
    return;
  }
  if (d == "Film") return require_world(t, false), option_directive(t, options_.film);
  if (d == "Sampler") return require_world(t, false), option_directive(t, options_.sampler);
  if (d == "PixelFilter") return require_world(t, false), option_directive(t, options_.filter);
  if (d == "Integrator") return require_world(t, false), option_directive(t, options_.integrator);
  if (d == "Accelerator") return require_world(t, false), option_directive(t, options_.accelerator);
  if (d == "WorldBegin") return world_begin(t);
  if (d == "WorldEnd") {
    pbrt_warn(warnings(), t.loc, "WorldEnd is not a pbrt-v4 directive (pbrt-v3); ignored");
    return;
  }
  if (d == "Shape") return shape(t);
  if (d == "Material") return material(t);
  if (d == "MakeNamedMaterial") return make_named_material(t);
  if (d == "NamedMaterial") {
    require_world(t, true);
    gs_.material = string_arg(t);
    referenced_.emplace(gs_.material, t.loc);
    return;
  }
  if (d == "Texture") return texture(t);
  if (d == "LightSource") return light(t);
  if (d == "AreaLightSource") {
    require_world(t, true);
    PbrtEntity e = entity(t);
    gs_.area_light = map_pbrt_area_light(e, warnings());
    e.params.report_unused(warnings(), e.what(d));
    return;
  }
  if (d == "ColorSpace") {
    const std::string name = string_arg(t);
    if (name != "srgb")
      pbrt_warn(warnings(), t.loc,
                "ColorSpace \"" + name + "\" not supported: rgb values are read as linear sRGB");
    return;
  }
  if (d == "Option") {
    PbrtParams p = PbrtParams::parse(tok());
    for (const PbrtParam& o : p.all())
      pbrt_warn(warnings(), o.loc, "Option " + o.declaration() + " ignored");
    return;
  }
  if (d == "Attribute") {
    PbrtEntity e = entity(t);
    pbrt_warn(warnings(), t.loc,
              "Attribute \"" + e.type + "\" (default parameters) is not supported; ignored");
    return;
  }
  if (d == "MakeNamedMedium" || d == "MediumInterface") {
    if (d == "MakeNamedMedium") {
      entity(t);
    } else {
      string_arg(t);
      if (tok().peek().kind == Kind::kString) string_arg(t);
    }
    pbrt_warn(warnings(), t.loc, d + ": participating media are not supported; ignored");
    return;
  }
  if (d == "ObjectBegin") {
    require_world(t, true);
    const std::string name = string_arg(t);
    if (object_) t.loc.fail("ObjectBegin inside the definition begun at " + object_->str());
    pbrt_warn(warnings(), t.loc,
              "ObjectBegin \"" + name +
                  "\": object instancing is not supported yet; its shapes are skipped");
    stack_.push_back({gs_, false, t.loc});
    object_ = t.loc;
    return;
  }
  if (d == "ObjectEnd") {
    if (!object_) t.loc.fail("ObjectEnd without ObjectBegin");
    object_.reset();
    attribute_end(t, false);
    return;
  }
  if (d == "ObjectInstance") {
    require_world(t, true);
    const std::string name = string_arg(t);
    pbrt_warn(warnings(), t.loc,
              "ObjectInstance \"" + name + "\": object instancing is not supported yet; skipped");
    return;
  }
  if (d == "TransformTimes") {
    numbers(t, 2);
    pbrt_warn(warnings(), t.loc, "TransformTimes: animated transforms are not supported; ignored");
    return;
  }
  if (d == "ActiveTransform") {
    const PbrtToken w = tok().next();
    if (w.kind != Kind::kWord || (w.text != "All" && w.text != "StartTime" && w.text != "EndTime"))
      w.loc.fail("ActiveTransform expects All, StartTime or EndTime, got " + w.describe());
    if (w.text != "All")
      pbrt_warn(warnings(), t.loc,
                "ActiveTransform " + w.text +
                    ": animated transforms are not supported; both times get the same transform");
    return;
  }
  t.loc.fail("unknown directive " + t.describe());
}

bool PbrtParser::transform_directive(const PbrtToken& t) {
  const std::string& d = t.text;
  Transform& ctm = gs_.ctm;
  if (d == "Identity") {
    ctm = Transform();
  } else if (d == "Translate") {
    ctm = ctm * pbrt_translate(numbers(t, 3));
  } else if (d == "Scale") {
    ctm = ctm * pbrt_scale(numbers(t, 3), t.loc);
  } else if (d == "Rotate") {
    ctm = ctm * pbrt_rotate(numbers(t, 4), t.loc);
  } else if (d == "LookAt") {
    ctm = ctm * pbrt_look_at(numbers(t, 9), t.loc);
  } else if (d == "Transform") {
    ctm = pbrt_matrix(numbers(t, 16), t.loc);
  } else if (d == "ConcatTransform") {
    ctm = ctm * pbrt_matrix(numbers(t, 16), t.loc);
  } else if (d == "CoordinateSystem") {
    named_[string_arg(t)] = ctm;
  } else if (d == "CoordSysTransform") {
    const std::string name = string_arg(t);
    const auto it = named_.find(name);
    if (it == named_.end())
      pbrt_warn(warnings(), t.loc, "CoordSysTransform: unknown coordinate system \"" + name + "\"");
    else
      ctm = it->second;
  } else {
    return false;
  }
  return true;
}

void PbrtParser::option_directive(const PbrtToken& t, std::optional<PbrtEntity>& slot) {
  if (slot)
    pbrt_warn(warnings(), t.loc,
              t.text + " given again; the earlier one at " + slot->loc.str() + " is replaced");
  slot = entity(t);
}

void PbrtParser::world_begin(const PbrtToken& t) {
  if (in_world_) t.loc.fail("WorldBegin given twice");
  in_world_ = true;
  // pbrt resets the CTM and names the world frame; the options are complete now.
  gs_.ctm = Transform();
  named_["world"] = gs_.ctm;
  if (pbrt_camera_mirrors(options_.camera_to_world)) world_from_pbrt_ = scale({-1, 1, 1});
  map_pbrt_options(options_, world_from_pbrt_, scene_);
}

void PbrtParser::attribute_end(const PbrtToken& t, bool transform_only) {
  if (stack_.empty())
    t.loc.fail(t.text + " without a matching " +
               (transform_only ? "TransformBegin" : "AttributeBegin"));
  const SavedState& top = stack_.back();
  if (top.transform_only != transform_only)
    t.loc.fail(t.text + " closes the " +
               (top.transform_only ? "TransformBegin" : "AttributeBegin") + " at " + top.loc.str());
  if (transform_only)
    gs_.ctm = top.state.ctm;
  else
    gs_ = top.state;
  stack_.pop_back();
}

std::string PbrtParser::default_material() {
  if (!materials_.count(kDefaultMaterial))
    scene_.materials.push_back(
        {kDefaultMaterial, SceneParams(nlohmann::json{{"type", "diffuse"}, {"albedo", 0.5}},
                                       scene_.file, "/pbrt-default")});
  materials_.emplace(kDefaultMaterial, scene_.materials.size() - 1);
  return kDefaultMaterial;
}

void PbrtParser::shape(const PbrtToken& t) {
  require_world(t, true);
  PbrtEntity e = entity(t);
  if (object_) return;                          // instancing: reported at ObjectBegin
  if (gs_.material == "\x01interface") return;  // an interface material has no surface
  PbrtShapeContext ctx{
      world_from_pbrt_ * gs_.ctm, gs_.reverse_orientation, {sources_.back().dir, base_dir_}};
  std::vector<ShapeDesc> shapes = map_pbrt_shape(e, ctx, warnings());
  e.params.report_unused(warnings(), e.what("Shape"));
  const std::string mat = gs_.material.empty() ? default_material() : gs_.material;
  for (ShapeDesc& s : shapes) {
    s.material = mat;
    s.path = e.loc.str();
    if (gs_.area_light && !gs_.area_light->radiance.is_black()) {
      s.emission = gs_.area_light->radiance;
      s.two_sided_emission = gs_.area_light->two_sided;
    }
    scene_.shapes.push_back(std::move(s));
  }
}

void PbrtParser::add_material(const std::string& name, PbrtEntity e) {
  std::optional<nlohmann::json> m;
  if (e.type == "mix") {
    // The nearest of a mix is its first material (penumbra has no stochastic mix).
    const PbrtParam* p = e.params.find("materials", "string");
    if (!p || p->strings.size() != 2) e.loc.fail("mix needs \"string materials\" [two names]");
    const auto it = material_json_.find(p->strings[0]);
    if (it == material_json_.end()) p->loc.fail("unknown material \"" + p->strings[0] + "\"");
    e.params.find("amount", "float texture");
    pbrt_warn(warnings(), e.loc,
              "material \"mix\" rendered as its first material \"" + p->strings[0] + "\"");
    m = it->second;
  } else {
    m = map_pbrt_material(e, textures_, warnings());
  }
  e.params.report_unused(warnings(), "material \"" + e.type + "\"");
  if (!m) {  // interface: shapes with it are skipped
    material_json_[name] = nlohmann::json();
    return;
  }
  material_json_[name] = *m;
  scene_.materials.push_back({name, SceneParams(*m, e.loc.str(), "")});
  materials_[name] = scene_.materials.size() - 1;
}

void PbrtParser::material(const PbrtToken& t) {
  require_world(t, true);
  PbrtEntity e = entity(t);
  const std::string name = "material@" + e.loc.str();
  add_material(name, std::move(e));
  gs_.material = materials_.count(name) ? name : "\x01interface";
}

void PbrtParser::make_named_material(const PbrtToken& t) {
  require_world(t, true);
  const std::string name = string_arg(t);
  PbrtEntity e;
  e.loc = t.loc;
  e.params = PbrtParams::parse(tok());
  if (material_json_.count(name)) t.loc.fail("named material \"" + name + "\" redefined");
  e.type = e.params.get_string("type", "");
  if (e.type.empty()) t.loc.fail("MakeNamedMaterial \"" + name + "\" needs a \"string type\"");
  add_material(name, std::move(e));
}

void PbrtParser::texture(const PbrtToken& t) {
  require_world(t, true);
  const std::string name = string_arg(t);
  const std::string value_type = string_arg(t);
  if (value_type != "spectrum" && value_type != "float")
    t.loc.fail("Texture \"" + name + "\": type must be \"spectrum\" or \"float\", got \"" +
               value_type + "\"");
  PbrtEntity e = entity(t);
  if (textures_.count(name))
    pbrt_warn(warnings(), t.loc, "texture \"" + name + "\" redefined; the new one is used");
  textures_[name] = map_pbrt_texture(value_type, e, textures_, warnings());
  e.params.report_unused(warnings(), e.what("Texture"));
}

void PbrtParser::light(const PbrtToken& t) {
  require_world(t, true);
  PbrtEntity e = entity(t);
  std::optional<nlohmann::json> l = map_pbrt_light(e, world_from_pbrt_ * gs_.ctm, warnings());
  e.params.report_unused(warnings(), e.what("LightSource"));
  if (l) {
    scene_.lights.emplace_back(*l, e.loc.str(), "");
  }
}

void PbrtParser::finish() {
  if (!in_world_) {
    pbrt_warn(warnings(), {scene_.file, 1, 1}, "no WorldBegin: the scene is empty");
    map_pbrt_options(options_, world_from_pbrt_, scene_);
  }
  if (!stack_.empty())
    pbrt_warn(warnings(), stack_.back().loc, "AttributeBegin without AttributeEnd at the end");
  if (object_) object_->fail("ObjectBegin without ObjectEnd");
  // Named materials may be defined after their first use (pbrt resolves them at the end).
  for (const auto& [name, loc] : referenced_)
    if (!material_json_.count(name)) loc.fail("NamedMaterial: unknown material \"" + name + "\"");
  // Shapes whose named material is an interface are dropped.
  std::erase_if(scene_.shapes, [&](const ShapeDesc& s) { return !materials_.count(s.material); });
}

}  // namespace

SceneDesc parse_pbrt_scene(const std::string& text, const std::string& file_name,
                           const std::string& base_dir) {
  PbrtParser parser(file_name, base_dir);
  return parser.run(text, file_name);
}

SceneDesc load_pbrt_scene(const std::string& path) {
  return parse_pbrt_scene(read_file_contents(path), path, fs::path(path).parent_path().string());
}

}  // namespace penumbra
