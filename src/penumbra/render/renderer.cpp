#include "penumbra/render/renderer.h"

#include <algorithm>

#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"

namespace penumbra {

RenderStats render(const Camera& camera, const Integrator& integrator, const Sampler& sampler,
                   const FilterSampler& filter, Film& film, const RenderOptions& options) {
  const Timer timer;
  const int ts = std::max(1, options.tile_size);
  const int nx = (film.width() + ts - 1) / ts, ny = (film.height() + ts - 1) / ts;
  const size_t tiles = size_t(nx) * size_t(ny);
  const int spp = sampler.samples_per_pixel();
  std::atomic<uint64_t> rays{0};
  std::atomic<size_t> done{0};

  parallel_for(tiles, [&](size_t tile) {
    if (options.cancel && options.cancel->load(std::memory_order_relaxed)) return;
    const int x0 = int(tile % size_t(nx)) * ts, y0 = int(tile / size_t(nx)) * ts;
    const int x1 = std::min(x0 + ts, film.width()), y1 = std::min(y0 + ts, film.height());
    auto s = sampler.clone();
    RayCounter counter;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        for (int i = 0; i < spp; ++i) {
          // Dimensions in a fixed order: pixel offset, lens, time, then the integrator's.
          s->start_pixel_sample(x, y, i);
          CameraSample cs;
          const FilterSample fs = filter.sample(s->get_pixel_2d());
          cs.film = {float(x) + 0.5f + fs.offset.x, float(y) + 0.5f + fs.offset.y};
          cs.lens = s->get_2d();
          cs.time = s->get_1d();
          const Ray ray = camera.generate_ray(cs);
          film.add_sample(x, y, integrator.li(ray, *s, counter), fs.weight);
        }
    rays.fetch_add(counter.rays, std::memory_order_relaxed);
    const size_t n = done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (options.on_tile) options.on_tile(n, tiles);
  });

  RenderStats stats;
  stats.camera_rays = uint64_t(film.width()) * uint64_t(film.height()) * uint64_t(spp);
  stats.rays = rays.load();
  stats.tiles_done = done.load();
  stats.tiles_total = tiles;
  stats.seconds = timer.elapsed_s();
  return stats;
}

}  // namespace penumbra
