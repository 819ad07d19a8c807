#pragma once
/// Integrators solve for the image: each owns its render (pbrt-v4's Integrator::Render, Mitsuba 3's
/// Integrator::render); most only say what one camera sample sees (SamplingIntegrator::li) and run
/// on the shared progressive loop.
#include <string>

#include <fmt/format.h>

#include "penumbra/core/color.h"
#include "penumbra/core/error.h"
#include "penumbra/core/params.h"
#include "penumbra/core/ray.h"
#include "penumbra/render/render_stats.h"
#include "penumbra/render/sampler/sampler.h"
#include "penumbra/render/world.h"

namespace penumbra {

class RenderJob;

/// A light-transport algorithm bound to a world. `render` may keep state between its steps (a
/// photon map, a radiosity solution); a SamplingIntegrator's `li` is const and thread-safe.
class Integrator {
 public:
  virtual ~Integrator() = default;
  /// The registered name with its parameters.
  virtual std::string name() const = 0;
  /// Renders the job's film, honouring its options (spp, time limit, target error, checkpoints,
  /// cancellation).
  virtual RenderStats render(RenderJob& job) = 0;
};

/// An integrator that estimates the radiance of each camera sample independently (pbrt-v4's
/// ImageTileIntegrator / RayIntegrator, Mitsuba 3's SamplingIntegrator). Its render is the
/// progressive pass loop of render_passes: `preprocess` runs once before the first pass (a
/// photon map, a radiosity solve), `end_pass` after every pass (SPPM's photon pass).
class SamplingIntegrator : public Integrator {
 public:
  RenderStats render(RenderJob& job) override;
  /// Work before the first pass; may report progress and must return soon after
  /// job.cancelled() turns true. The default does nothing.
  virtual void preprocess(RenderJob& /*job*/) {}
  /// Called after each finished pass with the number of samples per pixel done so far.
  virtual void end_pass(RenderJob& /*job*/, int /*spp_done*/) {}
  /// Radiance arriving at the camera along `ray`.
  virtual Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const = 0;
  /// Renders samples [first, first + count) of every pixel of [x0, x1) x [y0, y1) into the job's
  /// film. The default calls li per sample, pixel by pixel with the sample index rising; an
  /// integrator may shade many samples at once (path's lanes) if the film receives the same
  /// values in the same order.
  virtual void render_tile(RenderJob& job, int x0, int y0, int x1, int y1, int first, int count,
                           RayCounter& counter) const;
};

/// The deepest recursion of the recursive integrators (whitted, distribution): each bounce is a
/// stack frame of a few hundred bytes, so this stays far from the smallest thread stacks.
inline constexpr int kMaxRecursionDepth = 1000;

/// `max_depth` of a recursive integrator `name`: the parameter, else `fallback` (the scene's or
/// --max-depth), both checked against [0, kMaxRecursionDepth] (a scene asking for 30,000
/// bounces between two mirrors must not overflow the call stack).
inline int recursion_depth(const ParamList& params, int fallback, const char* name) {
  if (fallback > kMaxRecursionDepth)
    throw Error(fmt::format("{}: max_depth {} is more than {}, the deepest recursion it supports "
                            "(path is iterative and has no limit)",
                            name, fallback, kMaxRecursionDepth));
  return static_cast<int>(params.get_int("max_depth", fallback, 0, kMaxRecursionDepth));
}

}  // namespace penumbra
