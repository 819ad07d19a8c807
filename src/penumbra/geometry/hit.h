#pragma once
/// The small hit record filled during traversal; the full surface interaction is computed once,
/// for the closest hit only, by the renderer.
#include <cmath>
#include <cstdint>
#include <limits>

#include "penumbra/geometry/float_error.h"

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

/// The exclusive bound on t for primitive `id` to replace `hit`. Closest hits are ordered by
/// (t, primitive id): at exactly the t of the hit so far, the lower id wins. So every structure,
/// whatever order it tests its primitives in (its tree, a packet, interleaved rays), returns the
/// one closest hit `brute` returns, even on coincident surfaces. (Within an instance, the object's
/// own ids; between instances, the lower instance id: accel/instance_bvh.cpp.)
inline float tie_bound(const Hit& hit, uint32_t id) {
  return id < hit.prim && hit.prim != kNoPrim ? next_float_up(hit.t) : hit.t;
}

/// Relative slack of box and cell culling: 2^-16.
inline constexpr float kCullSlack = 0x1p-16f;

/// A traversal skips a box or a cell only when it starts beyond this bound on the closest hit's
/// t, not beyond t itself. A primitive's computed t can lie well below the computed entry of a
/// box or cell that holds it: the watertight test's error is a few ulps of the distances along
/// the ray's dominant axis to the triangle's vertices, which exceed t when the triangle is large
/// and near (46 ulps of t were seen on a grid of unit quads 0.015 away). At a t equal to the hit
/// so far, the lower id must still be found (tie_bound), and a closer t must never be skipped.
/// The relative term covers the error proportional to t. The part proportional to the
/// primitive's size comes either from the boxes, which the BVHs grow at build by kCullSlack of
/// their largest extent (grow_box in accel/build/bvh_node.h), or, for structures of cells that
/// cannot grow, from `abs_slack`: kCullSlack times the largest extent of a primitive over the
/// largest |direction component| (cull_slack). The extra boxes and cells visited are rare; the
/// bound is renewed at each hit. What the rules cost together: docs/accel.md, "2026-12-07,
/// twenty-fifth session".
inline float cull_bound(float t, float abs_slack = 0.0f) {
  return t * (1.0f + kCullSlack) + abs_slack;
}

/// The bound a query culls at: cull_bound for closest hits. Any-hit queries cull at t itself (the
/// ray's tmax, as hit.t never shrinks before they end), as before these rules: no order decides
/// between their hits, and the multiply per box cost the BVH's occlusion rays instructions.
template <bool kAnyHit>
inline float query_cull(float t, float abs_slack = 0.0f) {
  if constexpr (kAnyHit)
    return t;
  else
    return cull_bound(t, abs_slack);
}

/// The absolute term of cull_bound for a ray with reciprocal direction `inv` (components +-inf
/// where the direction's are 0) in a set whose largest primitive extent is `max_extent`.
inline float cull_slack(float max_extent, const float (&inv)[3]) {
  // Comparisons, not std::fmin: without -ffinite-math-only GCC calls fminf (in a paired run the
  // kd-tree's camera rays on the bunny were 15 % slower with the calls).
  const float x = std::fabs(inv[0]), y = std::fabs(inv[1]), z = std::fabs(inv[2]);
  // Two minima in a row: nested, the outer choice compiled to a branch that random rays
  // mispredicted half the time.
  const float xy = x < y ? x : y;
  const float m = xy < z ? xy : z;
  return kCullSlack * max_extent * m;
}

}  // namespace penumbra
