#pragma once
/// Deterministic ray sets for accel-bench and the parallel loop that times them.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "penumbra/core/bounds.h"
#include "penumbra/core/ray.h"
#include "penumbra/geometry/hit.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra::app {

/// Primary rays (row by row, through pixel centres) of a width x height pinhole camera with a
/// 40-degree vertical field of view, placed outside `bounds` on a fixed oblique direction from
/// its centre and framing its bounding sphere. tmin = 0, tmax = infinity.
std::vector<Ray> primary_rays(const Bounds3& bounds, int width, int height);

/// `n` rays with origins uniform in `bounds` and directions uniform on the unit sphere, from a
/// fixed seed (the same rays for every thread count). tmin = 0, tmax = infinity.
std::vector<Ray> incoherent_rays(const Bounds3& bounds, size_t n, uint64_t seed);

/// The rays of a path tracer at its first bounce, generated from the closest hits of `camera`
/// rays (`hits[i]` for `camera[i]`; misses are skipped) in order: per camera hit, one diffuse
/// bounce and one shadow ray, both starting at the hit point moved 1e-5 of the scene's radius off
/// the surface along its geometric normal turned towards the camera ray.
struct PathRays {
  /// Closest-hit queries in cosine-distributed directions about that normal (a diffuse BSDF's
  /// importance sampling), tmax = infinity.
  std::vector<Ray> bounce;
  /// Occlusion queries towards a point of the light, tmax just short of it, from the points that
  /// face it: a uniform point (by area) of the `lights` triangles when there are any (a scene's
  /// emitters), else of a square of side 0.5 |diagonal| centred 0.25 |diagonal| above the
  /// scene's bounds (+y).
  std::vector<Ray> shadow;
};
PathRays path_rays(const PrimitiveSet& prims, const std::vector<Ray>& camera,
                   const std::vector<Hit>& hits, uint64_t seed,
                   const std::vector<uint32_t>& lights = {});

/// Calls trace(begin, end) on chunks covering [0, n) in parallel (on the current thread limit);
/// returns the wall time in seconds.
double time_chunks(size_t n, const std::function<void(size_t, size_t)>& trace);

}  // namespace penumbra::app
