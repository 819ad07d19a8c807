#include "penumbra/scene/pbrt_parser.h"

#include <cmath>
#include <filesystem>

#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/pbrt_parser_state.h"
#include "penumbra/scene/pbrt_shapes.h"
#include "penumbra/scene/pbrt_transforms.h"

namespace penumbra {

namespace pbrt_detail {

namespace fs = std::filesystem;

constexpr int kMaxIncludeDepth = 64;

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
  sources_.push_back({std::make_unique<PbrtTokenizer>(pbrt_read_file(path, t.loc), path),
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
    options_.camera_to_world = gs_.ctm.start.inverted();
    named_["camera"] = {gs_.ctm.start.inverted(), gs_.ctm.end.inverted()};
    if (gs_.ctm.animated())
      pbrt_warn(warnings(), t.loc,
                "the camera moves (its transform differs at the start and the end): penumbra's "
                "cameras do not move, the start transform is used");
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
  if (reported_directive(t)) return;
  t.loc.fail("unknown directive " + t.describe());
}

// Directives penumbra reads but does not represent: each is reported and skipped (their
// arguments are consumed). False when `t` is none of them.
bool PbrtParser::reported_directive(const PbrtToken& t) {
  const std::string& d = t.text;
  if (d == "ColorSpace") {
    const std::string name = string_arg(t);
    if (name != "srgb")
      pbrt_warn(warnings(), t.loc,
                "ColorSpace \"" + name + "\" not supported: rgb values are read as linear sRGB");
    return true;
  }
  if (d == "Option") {
    PbrtParams p = PbrtParams::parse(tok());
    for (const PbrtParam& o : p.all())
      pbrt_warn(warnings(), o.loc, "Option " + o.declaration() + " ignored");
    return true;
  }
  if (d == "Attribute") {
    PbrtEntity e = entity(t);
    pbrt_warn(warnings(), t.loc,
              "Attribute \"" + e.type + "\" (default parameters) is not supported; ignored");
    return true;
  }
  if (d == "MakeNamedMedium" || d == "MediumInterface") {
    if (d == "MakeNamedMedium") {
      entity(t);
    } else {
      string_arg(t);
      if (tok().peek().kind == Kind::kString) string_arg(t);
    }
    pbrt_warn(warnings(), t.loc, d + ": participating media are not supported; ignored");
    return true;
  }
  if (d == "ObjectBegin" || d == "ObjectEnd" || d == "ObjectInstance") {
    object_directive(t);
    return true;
  }
  return false;
}

bool PbrtParser::transform_directive(const PbrtToken& t) {
  const std::string& d = t.text;
  // Each directive changes the transforms that ActiveTransform selects (both by default), as
  // pbrt-v4's graphics state does; CoordSysTransform sets both.
  const auto apply = [&](auto&& f) {
    if (gs_.active & kStartTransform) gs_.ctm.start = f(gs_.ctm.start);
    if (gs_.active & kEndTransform) gs_.ctm.end = f(gs_.ctm.end);
  };
  const auto concat = [&](const Transform& m) { apply([&](const Transform& c) { return c * m; }); };
  if (d == "Identity") {
    apply([](const Transform&) { return Transform(); });
  } else if (d == "Translate") {
    concat(pbrt_translate(numbers(t, 3)));
  } else if (d == "Scale") {
    concat(pbrt_scale(numbers(t, 3), t.loc));
  } else if (d == "Rotate") {
    concat(pbrt_rotate(numbers(t, 4), t.loc));
  } else if (d == "LookAt") {
    concat(pbrt_look_at(numbers(t, 9), t.loc));
  } else if (d == "Transform") {
    const Transform m = pbrt_matrix(numbers(t, 16), t.loc);
    apply([&](const Transform&) { return m; });
  } else if (d == "ConcatTransform") {
    concat(pbrt_matrix(numbers(t, 16), t.loc));
  } else if (d == "CoordinateSystem") {
    named_[string_arg(t)] = gs_.ctm;
  } else if (d == "CoordSysTransform") {
    const std::string name = string_arg(t);
    const auto it = named_.find(name);
    if (it == named_.end())
      pbrt_warn(warnings(), t.loc, "CoordSysTransform: unknown coordinate system \"" + name + "\"");
    else
      gs_.ctm = it->second;
  } else if (d == "ActiveTransform") {
    const PbrtToken w = tok().next();
    if (w.kind == Kind::kWord && w.text == "All")
      gs_.active = kStartTransform | kEndTransform;
    else if (w.kind == Kind::kWord && w.text == "StartTime")
      gs_.active = kStartTransform;
    else if (w.kind == Kind::kWord && w.text == "EndTime")
      gs_.active = kEndTransform;
    else
      w.loc.fail("ActiveTransform expects All, StartTime or EndTime, got " + w.describe());
  } else if (d == "TransformTimes") {
    transform_times(t);
  } else {
    return false;
  }
  return true;
}

void PbrtParser::transform_times(const PbrtToken& t) {
  require_world(t, false);
  const std::vector<double> v = numbers(t, 2);
  if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && v[0] < v[1]))
    t.loc.fail("TransformTimes: the start time must be before the end time, got " +
               pbrt_format_number(v[0]) + " and " + pbrt_format_number(v[1]));
  options_.start_time = v[0];
  options_.end_time = v[1];
}

const Transform& PbrtParser::static_ctm(const PbrtToken& t, const std::string& what) {
  if (gs_.ctm.animated())
    pbrt_warn(warnings(), t.loc,
              what +
                  " cannot move in penumbra: its transform at the start time is used (the "
                  "CTM differs at the end time)");
  return gs_.ctm.start;
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
  gs_.ctm = {};
  gs_.active = kStartTransform | kEndTransform;
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
  if (transform_only) {  // the CTM and ActiveTransform, as pbrt-v3 restores them
    gs_.ctm = top.state.ctm;
    gs_.active = top.state.active;
  } else {
    gs_ = top.state;
  }
  stack_.pop_back();
}

}  // namespace pbrt_detail

SceneDesc parse_pbrt_scene(const std::string& text, const std::string& file_name,
                           const std::string& base_dir) {
  pbrt_detail::PbrtParser parser(file_name, base_dir);
  return parser.run(text, file_name);
}

SceneDesc load_pbrt_scene(const std::string& path) {
  return parse_pbrt_scene(read_file_contents(path), path,
                          std::filesystem::path(path).parent_path().string());
}

}  // namespace penumbra
