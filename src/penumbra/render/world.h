#pragma once
/// The world a renderer traces: the scene's primitives, an acceleration structure over them, the
/// instanced objects (each with its own bottom-level structure of the same kind, under a top-level
/// BVH over the instances: accel/instance_bvh.h), the materials and every light: the scene's point,
/// directional and environment lights, one area light per emissive shape, and the background as a
/// constant environment light.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/accel/instance_bvh.h"
#include "penumbra/geometry/primitive_set.h"
#include "penumbra/render/light/light.h"
#include "penumbra/render/material/material.h"
#include "penumbra/render/surface_interaction.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Rays traced by one thread (summed by the renderer), and the clock ticks spent tracing them.
struct RayCounter {
  uint64_t rays = 0;
  uint64_t traversal_ticks = 0;  ///< in tick_count() units, estimated from one ray in 17
};

/// A cheap monotonic tick (the time-stamp counter on x86-64, else nanoseconds), for the share of
/// render time spent in traversal: only ratios of ticks are used.
uint64_t tick_count();

/// An emissive shape: its primitives (ids first .. first + count - 1) emit `radiance`.
struct Emitter {
  uint32_t shape = 0;
  uint32_t first_prim = 0, prim_count = 0;
  Rgb radiance;
  bool two_sided = false;
};

/// Scene geometry, acceleration structure, materials and lights, ready for tracing.
class World {
 public:
  /// Builds the world of `desc` with the acceleration structure named by `accel_spec`.
  World(const SceneDesc& desc, const std::string& accel_spec);

  /// Closest hit record along `ray` (scene primitives and instances); true when there is one.
  bool closest_hit(const Ray& ray, Hit& hit) const;
  /// closest_hit, adding to `cost` the work of every structure it asked (the scene's, the top
  /// level over instances and the instances' own): the cost view's query.
  bool closest_hit_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const;
  /// Whether anything blocks `ray`, adding to `cost` the work of every structure it asked.
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const;
  /// Closest hit along `ray`; fills `si` and returns true when there is one.
  bool intersect(const Ray& ray, SurfaceInteraction& si, RayCounter& counter) const;
  /// closest_hit, counted (and one ray in 17 timed) in `counter` as intersect counts it: for
  /// shaders that complete the interaction themselves.
  bool closest_hit(const Ray& ray, Hit& hit, RayCounter& counter) const;
  /// True when the interaction of scene primitive `prim` is its plane's alone: a static triangle of
  /// a shape without shading normals, uvs or emission (path's lanes compute those eight at once).
  bool plain_triangle(uint32_t prim) const {
    const ShapeInfo& s = shapes_[prims_.origin(prim).shape];
    return prims_.kind(prim) == PrimKind::kTriangle && !prims_.moving(prim) && s.mesh < 0 &&
           !s.area_light;
  }
  /// True when the shape's transform mirrors it, so its triangles' front side is flipped.
  bool shape_flips_normal(uint32_t shape) const { return shapes_[shape].flip_normal; }
  /// True when something blocks `ray` on (tmin, tmax).
  bool occluded(const Ray& ray, RayCounter& counter) const;
  /// Completes the surface interaction of a hit found by the accelerator.
  void interaction(const Ray& ray, const Hit& hit, SurfaceInteraction& si) const;
  /// Radiance arriving along a ray that left the scene: the sum of the infinite lights' Le.
  Rgb escaped(const Ray& ray) const;

  /// Area times unit front normal of a planar primitive (zero vector for a sphere); at time 0 for
  /// a moving one (emitters, its users, never move).
  Vec3 area_normal(uint32_t prim) const;

  const PrimitiveSet& primitives() const { return prims_; }
  const Accelerator& accelerator() const { return *accel_; }
  /// The top level over the instances (empty when the scene has none).
  const InstanceBvh& instances() const { return instanced_; }
  /// True when the scene places instanced objects.
  bool has_instances() const { return !instanced_.instances().empty(); }
  /// Bytes of the geometry and its structures: the scene's primitives and structure, each
  /// instanced object's primitives and bottom-level structure (once), and the top level.
  size_t geometry_bytes() const;
  /// Every light: the scene's, then the area lights (in emitter order), then the background.
  const std::vector<const Light*>& lights() const { return light_list_; }
  /// The infinite lights (environment maps, the background), a subset of lights().
  const std::vector<const Light*>& infinite_lights() const { return infinite_lights_; }
  /// The area light of emitter i of emitters().
  const Light& area_light(size_t emitter) const { return *lights_[first_area_light_ + emitter]; }
  /// The emissive shapes.
  const std::vector<Emitter>& emitters() const { return emitters_; }
  /// Per shape (PrimOrigin::shape of its primitives), for integrators that mesh the scene
  /// (radiosity): its material, its emitted radiance (on the front side, the side area_normal
  /// points to, or both sides when two-sided) when emissive.
  size_t shape_count() const { return shapes_.size(); }
  const Material& shape_material(uint32_t shape) const { return *shapes_[shape].material; }
  const std::optional<Rgb>& shape_emission(uint32_t shape) const { return shapes_[shape].emission; }
  bool shape_emits_both_sides(uint32_t shape) const { return shapes_[shape].two_sided; }
  /// The scene's background radiance (also an infinite light when not black).
  Rgb background() const { return background_; }
  /// Bounds of the scene's geometry.
  const Bounds3& bounds() const { return bounds_; }

 private:
  /// Per-shape data the interaction needs beyond the primitive set.
  struct ShapeInfo {
    const Material* material = nullptr;
    std::optional<Rgb> emission;
    const Light* area_light = nullptr;  ///< when emissive
    bool two_sided = false;
    bool flip_normal = false;  ///< transform swaps handedness: the front side flips
    int mesh = -1;             ///< index into meshes_ for shading normals and uvs, or -1
    int mesh_end = -1;         ///< a moving mesh's shading normals at time 1, or -1
  };
  /// Throws InputError (file, the shape's JSON path, the primitive and its coordinates) when a
  /// primitive from `first` on has a NaN, infinite or larger than kMaxCoordinate coordinate.
  void check_magnitudes(const std::string& file, const ShapeDesc& sd, const PrimitiveSet& prims,
                        uint32_t first) const;
  /// Adds the primitives of shape `sd` to `prims` as shape `shape` (transformed by its
  /// to_world) and returns its ShapeInfo.
  ShapeInfo add_shape(const SceneDesc& desc, const ShapeDesc& sd, uint32_t shape,
                      const std::vector<std::string>& material_names, PrimitiveSet& prims);
  /// The interaction of `hit` on `prims` along `ray`, in the space of `prims`.
  void local_interaction(const PrimitiveSet& prims, const Ray& ray, const Hit& hit,
                         SurfaceInteraction& si) const;
  /// Builds the instanced objects' primitives and structures and the top level over instances.
  void build_instances(const SceneDesc& desc, const std::string& accel_spec,
                       const std::vector<std::string>& material_names);

  PrimitiveSet prims_;
  std::unique_ptr<Accelerator> accel_;
  std::vector<std::unique_ptr<PrimitiveSet>> object_prims_;  ///< per object, object space
  std::vector<std::unique_ptr<Accelerator>> object_accels_;  ///< per object, over object_prims_
  InstanceBvh instanced_;
  Bounds3 bounds_;  ///< of the primitives and every instance
  std::vector<std::unique_ptr<Material>> materials_;
  std::vector<std::unique_ptr<Light>> lights_;  ///< owned, in the order of light_list_
  std::vector<const Light*> light_list_, infinite_lights_;
  size_t first_area_light_ = 0;
  std::vector<ShapeInfo> shapes_;
  std::vector<TriangleMesh> meshes_;  ///< world-space normals and uvs (positions dropped)
  std::vector<Emitter> emitters_;
  Rgb background_;
};

}  // namespace penumbra
