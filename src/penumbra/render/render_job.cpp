#include "penumbra/render/render_job.h"

#include "penumbra/render/camera/camera_registry.h"
#include "penumbra/render/integrator/integrator_registry.h"
#include "penumbra/render/sampler/sampler_registry.h"

namespace penumbra {

RenderJob::RenderJob(SceneDesc desc) : scene(std::move(desc)) {
  const RenderSettings& rs = scene.render;
  world = std::make_unique<World>(scene, rs.accel);
  camera = make_camera(scene.camera, rs.width, rs.height);
  sampler = make_sampler(rs.sampler, rs.spp, rs.seed);
  filter = make_filter(rs.filter);
  filter_sampler = std::make_unique<FilterSampler>(*filter);
  film = std::make_unique<Film>(rs.width, rs.height);
  integrator = make_integrator(rs.integrator, *world, rs);
}

RenderStats RenderJob::run() {
  return integrator->render(*this);
}

Ray RenderJob::camera_ray(Sampler& s, int x, int y, int index, float& filter_weight) const {
  s.start_pixel_sample(x, y, index);
  const FilterSample fs = filter_sampler->sample(s.get_pixel_2d());
  CameraSample cs;
  cs.film = {float(x) + 0.5f + fs.offset.x, float(y) + 0.5f + fs.offset.y};
  cs.lens = s.get_2d();
  cs.time = s.get_1d();
  filter_weight = fs.weight;
  return camera->generate_ray(cs);
}

}  // namespace penumbra
