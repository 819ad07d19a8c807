#pragma once
/// The plain description of a scene, as read from a scene file: no renderer types. The renderer
/// creates cameras, materials and lights from these records by their type names.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/core/transform.h"
#include "penumbra/geometry/primitive_set.h"
#include "penumbra/geometry/triangle_mesh.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Settings of a render; command-line flags override them.
struct RenderSettings {
  int width = 256, height = 256;
  int spp = 1;
  /// Maximum bounces when the scene or the command line sets it; unset, each integrator has its
  /// own default (8 for whitted and distribution, unbounded for path).
  std::optional<int> max_depth;
  /// The bound of integrators that need one when none is set.
  static constexpr int kDefaultMaxDepth = 8;
  uint64_t seed = 0;
  std::string integrator = "whitted";
  std::string accel = "bvh";
  std::string sampler = "independent";
  std::string filter = "box";
  Rgb background{0.0f};  ///< radiance of rays that leave the scene
};

/// A named material: its type ("diffuse", "mirror", "dielectric", ...) and parameters.
struct MaterialDesc {
  std::string name;
  SceneParams params;
};

/// One shape in object space with its object-to-world transform.
struct ShapeDesc {
  /// Sphere, parallelogram or triangle mesh (inline or loaded from OBJ/PLY).
  std::variant<SphereData, QuadData, TriangleMesh> geometry;
  Transform to_world;
  /// For a moving shape, the object-to-world transform at time 1 ("transform_end"); to_world is
  /// then the one at time 0 and vertices move linearly between the two (see PrimitiveSet).
  std::optional<Transform> to_world_end;
  std::string material;         ///< name of a MaterialDesc
  std::optional<Rgb> emission;  ///< radiance emitted on the front side, when emissive
  bool two_sided_emission = false;
  std::string path;  ///< JSON path, for messages
  std::string name;  ///< optional "name" from the file ("" when absent)
};

/// A named object: shapes defined once, in object space (each shape's to_world maps it into the
/// object's space), placed any number of times by instances. Its shapes are static and not
/// emissive (as in pbrt-v4, where area lights in instances are refused).
struct ObjectDesc {
  std::string name;
  std::vector<ShapeDesc> shapes;
  std::string path;  ///< JSON path (or FILE:LINE for pbrt), for messages
};

/// One placement of an object: the object-to-world transform of its shapes.
struct InstanceDesc {
  uint32_t object = 0;  ///< index into SceneDesc::objects
  Transform to_world;
  std::string path;  ///< JSON path, for messages
  std::string name;  ///< optional "name" from the file ("" when absent)
};

/// An encoded image (PNG or JPEG bytes) that a scene file holds rather than names: a glTF image
/// from a data: URI, a .glb's bufferView or an external file read by the importer. An image
/// texture whose "file" equals `name` decodes these bytes instead of reading a file.
struct EmbeddedImage {
  std::string name;                          ///< "FILE#/images/N": what texture parameters refer to
  std::string mime_type;                     ///< "image/png" or "image/jpeg"
  std::shared_ptr<const std::string> bytes;  ///< the encoded file, shared between copies
};

/// Everything a scene file describes.
struct SceneDesc {
  std::string file;         ///< the scene file, for messages
  std::string description;  ///< optional free text (provenance, notes)
  SceneParams camera;       ///< type "pinhole" (later: thin-lens fields)
  RenderSettings render;
  std::vector<MaterialDesc> materials;
  std::vector<SceneParams> lights;  ///< type "point", ...
  std::vector<ShapeDesc> shapes;
  std::vector<ObjectDesc> objects;      ///< named objects, placed by `instances`
  std::vector<InstanceDesc> instances;  ///< placements of objects
  std::vector<EmbeddedImage> images;    ///< encoded images that textures name (glTF)
  /// Problems that did not stop loading ("FILE:PLACE: message"): what an importer skipped,
  /// approximated or did not read, and the warnings of mesh files (an OBJ polygon that is not
  /// planar). The CLI prints them.
  std::vector<std::string> warnings;
};

}  // namespace penumbra
