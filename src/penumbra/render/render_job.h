#pragma once
/// One render, assembled in one place: the scene, the world built from it, the camera, sampler,
/// filter, film and integrator its settings name, and the options of the run. The CLI and the
/// tests build renders through it; later front ends (Python bindings, distributed rendering) are
/// meant to as well.
#include <memory>
#include <string>

#include "penumbra/render/camera/camera.h"
#include "penumbra/render/film.h"
#include "penumbra/render/filter/filter.h"
#include "penumbra/render/filter/filter_sampler.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/render_stats.h"
#include "penumbra/render/sampler/sampler.h"
#include "penumbra/render/world.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Everything one render needs. Members are public so that a test can swap one part (a camera,
/// a sampler) before running; the integrator refers to `world`, which must not be replaced after
/// the integrator is made.
class RenderJob {
 public:
  /// Builds the world, camera, sampler, filter, film and integrator that `desc.render` names;
  /// throws Error / InputError for anything unknown or malformed.
  explicit RenderJob(SceneDesc desc);
  RenderJob(const RenderJob&) = delete;
  RenderJob& operator=(const RenderJob&) = delete;

  /// Runs the integrator's render into `film`.
  RenderStats run();
  /// True once the options' cancel flag is set (integrators poll it in long steps).
  bool cancelled() const {
    return options.cancel && options.cancel->load(std::memory_order_relaxed);
  }
  /// Positions `s` at sample `index` of pixel (x, y) and draws the camera ray, with dimensions in
  /// a fixed order (pixel offset, lens, time) before the integrator's; `filter_weight` receives
  /// the reconstruction filter's weight of the sample.
  Ray camera_ray(Sampler& s, int x, int y, int index, float& filter_weight) const;
  /// The camera sample of pixel (x, y) from its numbers (pixel offset, lens, time), as
  /// camera_ray makes it: for a caller that draws the numbers itself (path's lanes).
  CameraSample camera_sample(int x, int y, Vec2 u_pixel, Vec2 u_lens, float u_time,
                             float& filter_weight) const {
    const FilterSample fs = filter_sampler->sample(u_pixel);
    CameraSample cs;
    cs.film = {float(x) + 0.5f + fs.offset.x, float(y) + 0.5f + fs.offset.y};
    cs.lens = u_lens;
    cs.time = u_time;
    filter_weight = fs.weight;
    return cs;
  }
  /// Passes a warning to options.on_warning, when set.
  void warn(const std::string& message) const {
    if (options.on_warning) options.on_warning(message);
  }
  /// Reports preprocessing progress through options.on_preprocess, when set.
  void report_preprocess(const char* what, double fraction) const {
    if (options.on_preprocess) options.on_preprocess(what, fraction);
  }

  SceneDesc scene;
  std::unique_ptr<World> world;
  std::unique_ptr<Camera> camera;
  std::unique_ptr<Sampler> sampler;  ///< the prototype, cloned per tile
  std::unique_ptr<Filter> filter;
  std::unique_ptr<FilterSampler> filter_sampler;
  std::unique_ptr<Film> film;
  std::unique_ptr<Integrator> integrator;
  RenderOptions options;
};

}  // namespace penumbra
