#pragma once
/// Internal to the pbrt reader: the parser's state (open files, graphics state, options, named
/// things) shared by pbrt_parser.cpp (tokens, Include, transforms, attributes, options) and
/// pbrt_world.cpp (shapes, materials, textures, lights, the end of the file). Not a public API.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/core/transform.h"
#include "penumbra/scene/pbrt_lights.h"
#include "penumbra/scene/pbrt_materials.h"
#include "penumbra/scene/pbrt_options.h"
#include "penumbra/scene/pbrt_params.h"
#include "penumbra/scene/pbrt_tokenizer.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra::pbrt_detail {

using Kind = PbrtToken::Kind;

/// The name of pbrt's default material (diffuse, reflectance 0.5), created when first needed.
inline constexpr const char* kDefaultMaterial = "pbrt-default";
/// The current material of shapes that are not surfaces (pbrt's "interface").
inline constexpr const char* kInterface = "\x01interface";

/// The two transformation matrices of pbrt-v4's graphics state: at the start and at the end of
/// TransformTimes. Shapes whose two differ move (ShapeDesc::to_world_end).
struct TransformPair {
  Transform start, end;
  bool animated() const { return !(start.matrix() == end.matrix()); }
};

/// ActiveTransform's bits: which of the pair the transform directives change.
inline constexpr unsigned kStartTransform = 1, kEndTransform = 2;

/// What AttributeBegin saves and AttributeEnd restores.
struct GraphicsState {
  TransformPair ctm;
  unsigned active = kStartTransform | kEndTransform;  ///< ActiveTransform
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

/// Reads one scene: directives in, SceneDesc out.
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
  bool reported_directive(const PbrtToken& t);
  void option_directive(const PbrtToken& t, std::optional<PbrtEntity>& slot);
  void world_begin(const PbrtToken& t);
  void attribute_end(const PbrtToken& t, bool transform_only);
  void shape(const PbrtToken& t);
  void object_directive(const PbrtToken& t);
  void material(const PbrtToken& t);
  void make_named_material(const PbrtToken& t);
  void texture(const PbrtToken& t);
  void light(const PbrtToken& t);
  std::string default_material();
  void add_material(const std::string& name, PbrtEntity e);
  void finish();
  void require_world(const PbrtToken& t, bool world);
  /// The CTM at a directive that cannot move (a light, an instance, an emitter): its start
  /// transform, with a warning naming `what` when the CTM is animated.
  const Transform& static_ctm(const PbrtToken& t, const std::string& what);
  void transform_times(const PbrtToken& t);
  void set_motion(ShapeDesc& s, const PbrtLoc& loc);

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
  std::map<std::string, TransformPair> named_;  ///< named coordinate systems
  PbrtOptions options_;
  bool in_world_ = false;
  Transform world_from_pbrt_;      ///< the mirror x -> -x, or the identity (set at WorldBegin)
  bool moving_ = false;            ///< some shape moves (the camera then gets its shutter)
  std::optional<PbrtLoc> object_;  ///< inside ObjectBegin ... ObjectEnd
  size_t object_index_ = 0;        ///< the object being defined (index in scene_.objects)
  std::map<std::string, size_t> objects_;  ///< object names -> index in scene_.objects
  /// An ObjectInstance, resolved at the end (pbrt-v4 resolves them after parsing too).
  struct PendingInstance {
    std::string name;
    Transform to_world;
    PbrtLoc loc;
  };
  std::vector<PendingInstance> instances_;
  std::map<std::string, size_t> materials_;    ///< name -> index in scene_.materials
  std::map<std::string, PbrtLoc> referenced_;  ///< NamedMaterial names -> first use
  std::map<std::string, nlohmann::json> material_json_;
  PbrtTextures textures_;
  int anonymous_ = 0;
};

}  // namespace penumbra::pbrt_detail
