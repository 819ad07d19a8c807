#pragma once
/// Deterministic ray sets for accel-bench and the parallel loop that times them.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "penumbra/core/bounds.h"
#include "penumbra/core/ray.h"

namespace penumbra::app {

/// Primary rays (row by row, through pixel centres) of a width x height pinhole camera with a
/// 40-degree vertical field of view, placed outside `bounds` on a fixed oblique direction from
/// its centre and framing its bounding sphere. tmin = 0, tmax = infinity.
std::vector<Ray> primary_rays(const Bounds3& bounds, int width, int height);

/// `n` rays with origins uniform in `bounds` and directions uniform on the unit sphere, from a
/// fixed seed (the same rays for every thread count). tmin = 0, tmax = infinity.
std::vector<Ray> incoherent_rays(const Bounds3& bounds, size_t n, uint64_t seed);

/// Calls trace(begin, end) on chunks covering [0, n) in parallel (on the current thread limit);
/// returns the wall time in seconds.
double time_chunks(size_t n, const std::function<void(size_t, size_t)>& trace);

}  // namespace penumbra::app
