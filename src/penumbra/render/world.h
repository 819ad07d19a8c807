#pragma once
/// The world a renderer traces: the scene's primitives, an acceleration structure over them, the
/// materials, the lights and the emissive shapes.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/geometry/primitive_set.h"
#include "penumbra/render/light/light.h"
#include "penumbra/render/material/material.h"
#include "penumbra/render/surface_interaction.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Rays traced by one thread (summed by the renderer).
struct RayCounter {
  uint64_t rays = 0;
};

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

  /// Closest hit along `ray`; fills `si` and returns true when there is one.
  bool intersect(const Ray& ray, SurfaceInteraction& si, RayCounter& counter) const;
  /// True when something blocks `ray` on (tmin, tmax).
  bool occluded(const Ray& ray, RayCounter& counter) const;
  /// Completes the surface interaction of a hit found by the accelerator.
  void interaction(const Ray& ray, const Hit& hit, SurfaceInteraction& si) const;

  /// Area times unit front normal of a planar primitive (zero vector for a sphere); at time 0 for
  /// a moving one (emitters, its users, never move).
  Vec3 area_normal(uint32_t prim) const;

  const PrimitiveSet& primitives() const { return prims_; }
  const Accelerator& accelerator() const { return *accel_; }
  const std::vector<std::unique_ptr<Light>>& lights() const { return lights_; }
  const std::vector<Emitter>& emitters() const { return emitters_; }
  Rgb background() const { return background_; }

 private:
  /// Per-shape data the interaction needs beyond the primitive set.
  struct ShapeInfo {
    const Material* material = nullptr;
    std::optional<Rgb> emission;
    bool two_sided = false;
    bool flip_normal = false;  ///< transform swaps handedness: the front side flips
    int mesh = -1;             ///< index into meshes_ for shading normals and uvs, or -1
    int mesh_end = -1;         ///< a moving mesh's shading normals at time 1, or -1
  };

  PrimitiveSet prims_;
  std::unique_ptr<Accelerator> accel_;
  std::vector<std::unique_ptr<Material>> materials_;
  std::vector<std::unique_ptr<Light>> lights_;
  std::vector<ShapeInfo> shapes_;
  std::vector<TriangleMesh> meshes_;  ///< world-space normals and uvs (positions dropped)
  std::vector<Emitter> emitters_;
  Rgb background_;
};

}  // namespace penumbra
