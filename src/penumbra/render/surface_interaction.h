#pragma once
/// The full description of a ray's closest hit, computed once per hit from the small Hit record.
#include <cstdint>

#include "penumbra/core/color.h"
#include "penumbra/core/ray.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/geometry/hit.h"
#include "penumbra/render/light/light.h"

namespace penumbra {

class Material;
class Light;

/// A surface point seen along a ray.
struct SurfaceInteraction {
  Vec3 p;             ///< the point
  Vec3 p_error;       ///< absolute error bound of p per axis
  Vec3 ng;            ///< unit geometric normal (triangle winding / outward for spheres)
  Vec3 ns;            ///< unit shading normal, on the same side as ng
  Vec3 ss, ts;        ///< shading tangents: (ss, ts, ns) is orthonormal
  Vec2 uv;            ///< surface parameters
  Vec3 wo;            ///< unit direction back along the ray
  float t = 0;        ///< ray parameter of the hit
  uint32_t prim = 0;  ///< primitive id (of the instanced object's set when instance is set)
  uint32_t instance = kNoInstance;  ///< the instance hit, or kNoInstance
  uint32_t shape = 0;
  const Material* material = nullptr;
  const Light* area_light = nullptr;  ///< the area light of an emissive shape, else null
  Rgb emitted;  ///< radiance emitted towards wo (zero unless an emitter's lit side faces wo)

  /// This point as a point of its area light (for Light::pdf_li and Light::l).
  LightPoint light_point() const { return {p, ng, prim}; }

  /// World direction to the local shading frame (z = ns).
  Vec3 to_local(Vec3 w) const { return {dot(w, ss), dot(w, ts), dot(w, ns)}; }
  /// Local shading frame direction to world.
  Vec3 to_world(Vec3 w) const { return ss * w.x + ts * w.y + ns * w.z; }
  /// A ray leaving the surface in direction d, robust against self-intersection.
  Ray spawn_ray(Vec3 d, float time) const {
    Ray r;
    r.o = offset_ray_origin(p, p_error, ng, d);
    r.d = d;
    r.time = time;
    return r;
  }
  /// The shadow ray towards a light sample: to its point, or unbounded for infinite and
  /// directional lights (distance kInfinity).
  Ray shadow_ray(const LightSample& ls, float time) const {
    if (std::isinf(ls.distance)) return spawn_ray(ls.wi, time);
    return spawn_ray_to(p + ls.wi * ls.distance, time);
  }
  /// A ray from the surface towards `target` that stops just short of it (for shadow rays).
  Ray spawn_ray_to(Vec3 target, float time) const {
    Ray r;
    r.o = offset_ray_origin(p, p_error, ng, target - p);
    r.d = target - r.o;
    r.tmax = 1.0f - 1e-4f;  // the target's own surface must not occlude it
    r.time = time;
    return r;
  }
};

}  // namespace penumbra
