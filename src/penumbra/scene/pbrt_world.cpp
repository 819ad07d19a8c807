/// The world block of a pbrt scene: shapes with their material and area light, materials, textures,
/// light sources, and the checks at the end of the file.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

#include "penumbra/scene/pbrt_parser_state.h"
#include "penumbra/scene/pbrt_shapes.h"
#include "penumbra/scene/pbrt_transforms.h"
#include "penumbra/scene/transform_parser.h"

namespace penumbra::pbrt_detail {

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
  if (gs_.material == kInterface) return;  // an interface material has no surface
  const bool emits = gs_.area_light && !gs_.area_light->radiance.is_black();
  // A shape whose CTM differs at the start and the end moves, unless it cannot: shapes of
  // objects and emitters are static in penumbra (they get the start transform and a warning).
  const bool moves = gs_.ctm.animated() && !object_ && !emits;
  const Transform& start =
      moves ? gs_.ctm.start
            : static_ctm(t, object_ ? "a shape in an object definition" : "an emitting shape");
  // In an object definition the shape is kept in the object's space, the full CTM at the
  // shape (which includes the CTM at ObjectBegin); the instance then adds its own CTM and the
  // world mirror, as pbrt-v4 composes them.
  PbrtShapeContext ctx{object_ ? start : world_from_pbrt_ * start,
                       gs_.reverse_orientation,
                       {sources_.back().dir, base_dir_}};
  std::vector<ShapeDesc> shapes = map_pbrt_shape(e, ctx, warnings());
  e.params.report_unused(warnings(), e.what("Shape"));
  const std::string mat = gs_.material.empty() ? default_material() : gs_.material;
  for (ShapeDesc& s : shapes) {
    s.material = mat;
    s.path = e.loc.str();
    if (moves) set_motion(s, e.loc);
    if (emits) {
      if (object_) {  // as pbrt-v4: a warning, and the shape is kept without its light
        pbrt_warn(warnings(), e.loc,
                  "area lights are not supported with object instancing; the shape is kept "
                  "without its AreaLightSource");
      } else {
        s.emission = gs_.area_light->radiance;
        s.two_sided_emission = gs_.area_light->two_sided;
      }
    }
    if (object_)
      scene_.objects[object_index_].shapes.push_back(std::move(s));
    else
      scene_.shapes.push_back(std::move(s));
  }
}

void PbrtParser::set_motion(ShapeDesc& s, const PbrtLoc& loc) {
  const Transform end = world_from_pbrt_ * gs_.ctm.end;
  if (std::holds_alternative<SphereData>(s.geometry) && !is_similarity(end))
    loc.fail(
        "a sphere's transform at the end time must be a similarity (rotations, translations, "
        "uniform scales): penumbra has no ellipsoids");
  if (end.swaps_handedness() != s.to_world.swaps_handedness())
    loc.fail(
        "the transform at the end time mirrors the shape and the one at the start does not (or "
        "the reverse): the shape would turn inside out while moving");
  const double turn = pbrt_rotation_between(s.to_world, end) * 180.0 / std::numbers::pi;
  if (turn > 1.0)
    pbrt_warn(warnings(), loc,
              "the shape turns by " + pbrt_format_number(turn) +
                  " degrees between the start and the end time; penumbra moves its vertices on "
                  "straight lines, so mid-way it is " +
                  pbrt_format_number(100.0 * (1.0 - std::cos(turn * std::numbers::pi / 360.0))) +
                  " % closer to the axis than pbrt's interpolated rotation puts it");
  s.to_world_end = end;
  moving_ = true;
}

void PbrtParser::object_directive(const PbrtToken& t) {
  const std::string& d = t.text;
  if (d == "ObjectEnd") {
    if (!object_) t.loc.fail("ObjectEnd without ObjectBegin");
    object_.reset();
    attribute_end(t, false);
    return;
  }
  require_world(t, true);
  const std::string name = string_arg(t);
  if (d == "ObjectBegin") {
    if (object_) t.loc.fail("ObjectBegin inside the definition begun at " + object_->str());
    if (objects_.count(name))
      t.loc.fail("ObjectBegin \"" + name + "\": the object is already defined at " +
                 scene_.objects[objects_[name]].path);
    stack_.push_back({gs_, false, t.loc});  // ObjectBegin implies AttributeBegin
    object_ = t.loc;
    object_index_ = scene_.objects.size();
    objects_[name] = object_index_;
    scene_.objects.push_back({name, {}, t.loc.str()});
    return;
  }
  // ObjectInstance: the instance's CTM, then the world mirror; the object's own transforms are
  // in its shapes.
  if (object_)
    t.loc.fail("ObjectInstance \"" + name + "\" inside the definition begun at " + object_->str() +
               " (nested instancing is not supported)");
  instances_.push_back({name, world_from_pbrt_ * static_ctm(t, "an instance"), t.loc});
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
    if (!it->second.is_null()) m = it->second;  // (null: the first is an interface)
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
  gs_.material = materials_.count(name) ? name : std::string(kInterface);
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
  textures_[name] =
      map_pbrt_texture(value_type, e, textures_, {sources_.back().dir, base_dir_}, warnings());
  e.params.report_unused(warnings(), e.what("Texture"));
}

void PbrtParser::light(const PbrtToken& t) {
  require_world(t, true);
  PbrtEntity e = entity(t);
  std::optional<nlohmann::json> l =
      map_pbrt_light(e, world_from_pbrt_ * static_ctm(t, "a LightSource"),
                     {sources_.back().dir, base_dir_}, warnings());
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
  // The shutter matters only when something moves; a static scene keeps a camera without one.
  if (!moving_ && scene_.camera.json().contains("shutter")) {
    nlohmann::json cam = scene_.camera.json();
    cam.erase("shutter");
    scene_.camera = SceneParams(std::move(cam), scene_.camera.file(), scene_.camera.path());
  }
  // Named materials may be defined after their first use (pbrt resolves them at the end).
  for (const auto& [name, loc] : referenced_)
    if (!material_json_.count(name)) loc.fail("NamedMaterial: unknown material \"" + name + "\"");
  // Shapes whose named material is an interface are dropped.
  const auto interface = [&](const ShapeDesc& s) { return !materials_.count(s.material); };
  std::erase_if(scene_.shapes, interface);
  for (ObjectDesc& o : scene_.objects) std::erase_if(o.shapes, interface);
  // Instances by name, which may precede the definition.
  for (const PendingInstance& p : instances_) {
    const auto it = objects_.find(p.name);
    if (it == objects_.end()) p.loc.fail("ObjectInstance: unknown object \"" + p.name + "\"");
    scene_.instances.push_back({uint32_t(it->second), p.to_world, p.loc.str(), ""});
  }
}

}  // namespace penumbra::pbrt_detail
