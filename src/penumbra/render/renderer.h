#pragma once
/// The render loop: image tiles on all cores, each pixel sample independent of scheduling.
#include <atomic>
#include <cstdint>
#include <functional>

#include "penumbra/render/camera/camera.h"
#include "penumbra/render/film.h"
#include "penumbra/render/filter/filter_sampler.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/sampler/sampler.h"

namespace penumbra {

/// How to run a render and how to report on it.
struct RenderOptions {
  int tile_size = 16;
  /// Called after each finished tile with (tiles done, tiles in all), from worker threads
  /// (calls may overlap: the callee synchronises).
  std::function<void(size_t, size_t)> on_tile;
  /// When set and true, no further tiles are started; finished tiles are kept.
  const std::atomic<bool>* cancel = nullptr;
};

/// What a render did.
struct RenderStats {
  uint64_t camera_rays = 0;
  uint64_t rays = 0;  ///< every ray traced: camera, secondary and shadow
  double seconds = 0;
  size_t tiles_done = 0, tiles_total = 0;
  bool complete() const { return tiles_done == tiles_total; }
};

/// Renders `film` through `camera` with `integrator`; `sampler` is the prototype cloned per tile;
/// pixel sample positions are drawn from `filter` around each pixel centre. The result is
/// bit-identical for any thread count and tile order.
RenderStats render(const Camera& camera, const Integrator& integrator, const Sampler& sampler,
                   const FilterSampler& filter, Film& film, const RenderOptions& options);

}  // namespace penumbra
