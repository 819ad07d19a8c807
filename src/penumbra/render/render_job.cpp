#include "penumbra/render/render_job.h"

#include "penumbra/accel/registry.h"
#include "penumbra/render/camera/camera_registry.h"
#include "penumbra/render/integrator/integrator_registry.h"
#include "penumbra/render/sampler/sampler_registry.h"

namespace penumbra {
namespace {

// Runs make(); an Error it throws (an unknown name, a bad parameter) is re-thrown as an InputError
// naming the scene file and the setting's JSON path, "/render/KEY". Callers that override a
// setting (the CLI's --accel, ...) check their value first, so the error is the file's.
template <class Make>
auto setting(const SceneDesc& scene, const char* key, Make&& make) {
  try {
    return make();
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    if (scene.file.empty()) throw;
    throw InputError(scene.file, std::string("/render/") + key, e.what());
  }
}

}  // namespace

RenderJob::RenderJob(SceneDesc desc) : scene(std::move(desc)) {
  const RenderSettings& rs = scene.render;
  setting(scene, "accel", [&] { return make_accelerator(rs.accel); });  // the name, before building
  // The film first: a resolution beyond the memory limit is refused before the structure is built.
  film = setting(scene, "resolution", [&] { return std::make_unique<Film>(rs.width, rs.height); });
  world = std::make_unique<World>(scene, rs.accel);
  camera = make_camera(scene.camera, rs.width, rs.height);
  sampler = setting(scene, "sampler", [&] { return make_sampler(rs.sampler, rs.spp, rs.seed); });
  filter = setting(scene, "filter", [&] { return make_filter(rs.filter); });
  filter_sampler = std::make_unique<FilterSampler>(*filter);
  integrator =
      setting(scene, "integrator", [&] { return make_integrator(rs.integrator, *world, rs); });
}

RenderStats RenderJob::run() {
  return integrator->render(*this);
}

Ray RenderJob::camera_ray(Sampler& s, int x, int y, int index, float& filter_weight) const {
  s.start_pixel_sample(x, y, index);
  const Vec2 u_pixel = s.get_pixel_2d(), u_lens = s.get_2d();  // in this order
  return camera->generate_ray(camera_sample(x, y, u_pixel, u_lens, s.get_1d(), filter_weight));
}

}  // namespace penumbra
