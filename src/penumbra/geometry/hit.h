#pragma once
/// The small hit record filled during traversal; the full surface interaction is computed once,
/// for the closest hit only, by the renderer.
#include <cstdint>
#include <limits>

namespace penumbra {

/// Marks "no primitive".
inline constexpr uint32_t kNoPrim = std::numeric_limits<uint32_t>::max();

/// Marks "not in an instance" (a primitive of the scene's own, world-space set).
inline constexpr uint32_t kNoInstance = std::numeric_limits<uint32_t>::max();

/// Closest hit so far: ray parameter, primitive-specific (u, v), the primitive id and, for a hit
/// inside an instance (accel/instance_bvh.h), the instance (`prim` is then an id of the
/// instanced object's primitive set).
/// Triangles: (u, v) are the barycentrics of vertices 1 and 2. Quads: the parallelogram
/// coordinates along its two edges. Spheres: unused (the point determines everything).
struct Hit {
  float t = std::numeric_limits<float>::infinity();
  float u = 0, v = 0;
  uint32_t prim = kNoPrim;
  uint32_t instance = kNoInstance;

  bool valid() const { return prim != kNoPrim; }
};

}  // namespace penumbra
