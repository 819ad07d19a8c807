#include "penumbra/render/renderer.h"

#include <algorithm>
#include <cmath>

#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"
#include "penumbra/render/render_job.h"

namespace penumbra {

namespace {

/// A pass should take about this long when the schedule is chosen: short enough that progress,
/// checkpoints and time limits keep their pace, long enough that the end-of-pass barrier (idle
/// threads waiting for the last tile) costs little.
constexpr double kPassSeconds = 1.0;
/// Fewest samples per pixel before the error estimate may stop a render: with fewer, a pixel's
/// sample variance is too unreliable (a pixel whose first samples all miss a light reads as
/// converged).
constexpr int kMinSppForError = 8;

/// Counters summed over the tiles of a render.
struct Totals {
  std::atomic<uint64_t> rays{0}, traversal_ticks{0}, tile_ticks{0};
  std::atomic<size_t> tiles_done{0};
};

/// Renders samples [first, first + count) of every pixel of the tile [x0, x1) x [y0, y1).
void render_tile(RenderJob& job, const SamplingIntegrator& integrator, int x0, int y0, int x1,
                 int y1, int first, int count, Totals& totals) {
  const uint64_t start = tick_count();
  RayCounter counter;
  integrator.render_tile(job, x0, y0, x1, y1, first, count, counter);
  totals.rays.fetch_add(counter.rays, std::memory_order_relaxed);
  totals.traversal_ticks.fetch_add(counter.traversal_ticks, std::memory_order_relaxed);
  totals.tile_ticks.fetch_add(tick_count() - start, std::memory_order_relaxed);
}

}  // namespace

void SamplingIntegrator::render_tile(RenderJob& job, int x0, int y0, int x1, int y1, int first,
                                     int count, RayCounter& counter) const {
  auto s = job.sampler->clone();
  Film& film = *job.film;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int i = first; i < first + count; ++i) {
        float weight = 0.0f;
        const Ray ray = job.camera_ray(*s, x, y, i, weight);
        film.add_sample(x, y, li(ray, *s, counter), weight);
      }
}

RenderStats SamplingIntegrator::render(RenderJob& job) {
  return render_passes(job, *this);
}

RenderStats render_passes(RenderJob& job, SamplingIntegrator& integrator) {
  RenderStats stats;
  const RenderOptions& opt = job.options;
  Film& film = *job.film;
  stats.spp_target = job.sampler->samples_per_pixel();

  const Timer preprocess;
  integrator.preprocess(job);
  stats.preprocess_seconds = preprocess.elapsed_s();
  if (job.cancelled()) {
    stats.stop = StopReason::kCancelled;
    return stats;
  }

  const int ts = std::max(1, opt.tile_size);
  const int nx = (film.width() + ts - 1) / ts, ny = (film.height() + ts - 1) / ts;
  const size_t tiles = size_t(nx) * size_t(ny);
  stats.tiles_total = tiles;
  Totals totals;
  const Timer timer;
  double last_checkpoint = 0.0;
  int next = opt.pass_spp > 0 ? opt.pass_spp : 1;

  while (stats.spp_done < stats.spp_target) {
    const int first = stats.spp_done;
    int count = std::min(next, stats.spp_target - first);
    // A time limit: the pass must fit in what is left, at the pace of the passes so far.
    if (opt.time_limit_s > 0 && first > 0) {
      const double per_spp = timer.elapsed_s() / double(first);
      const double left = opt.time_limit_s - timer.elapsed_s();
      const double fit = per_spp > 0 ? std::floor(left / per_spp) : double(count);
      if (fit < 1.0) {
        stats.stop = StopReason::kTimeLimit;
        break;
      }
      count = int(std::min(double(count), fit));
    }

    const double pass_start = timer.elapsed_s();
    totals.tiles_done.store(0);
    parallel_for(tiles, [&](size_t tile) {
      if (job.cancelled()) return;
      const int x0 = int(tile % size_t(nx)) * ts, y0 = int(tile / size_t(nx)) * ts;
      render_tile(job, integrator, x0, y0, std::min(x0 + ts, film.width()),
                  std::min(y0 + ts, film.height()), first, count, totals);
      const size_t n = totals.tiles_done.fetch_add(1, std::memory_order_relaxed) + 1;
      if (opt.on_progress) {
        RenderProgress p;
        p.spp_done = n == tiles ? first + count : first;
        p.spp_target = stats.spp_target;
        p.fraction =
            (double(first) + double(count) * double(n) / double(tiles)) / double(stats.spp_target);
        p.elapsed_s = timer.elapsed_s();
        p.rays = totals.rays.load(std::memory_order_relaxed);
        p.mean_rel_error = stats.mean_rel_error;
        opt.on_progress(p);
      }
    });
    stats.tiles_done = totals.tiles_done.load();
    if (stats.tiles_done < tiles) {  // cancelled: the finished tiles of this pass stay
      stats.stop = StopReason::kCancelled;
      break;
    }
    stats.spp_done += count;
    ++stats.passes;
    integrator.end_pass(job, stats.spp_done);

    const double now = timer.elapsed_s();
    if (opt.checkpoint_s > 0 && opt.on_checkpoint && stats.spp_done < stats.spp_target &&
        now - last_checkpoint >= opt.checkpoint_s) {
      opt.on_checkpoint(film, stats.spp_done);
      last_checkpoint = timer.elapsed_s();
    }
    if (opt.target_error > 0 && stats.spp_done >= kMinSppForError) {
      stats.mean_rel_error = film.mean_relative_error();
      if (stats.mean_rel_error <= opt.target_error && stats.spp_done < stats.spp_target) {
        stats.stop = StopReason::kTargetError;
        break;
      }
    }
    // The next pass: double while a pass stays under kPassSeconds.
    if (opt.pass_spp == 0) {
      const double per_spp = (now - pass_start) / double(count);
      const double fit = per_spp > 0 ? std::floor(kPassSeconds / per_spp) : 2.0 * count;
      next = int(std::clamp(fit, 1.0, 2.0 * double(count)));
    }
  }
  if (opt.target_error > 0 && stats.mean_rel_error < 0)
    stats.mean_rel_error = film.mean_relative_error();

  stats.camera_rays = uint64_t(film.width()) * uint64_t(film.height()) * uint64_t(stats.spp_done);
  stats.rays = totals.rays.load();
  const uint64_t tile_ticks = totals.tile_ticks.load();
  stats.traversal_share =
      tile_ticks ? double(totals.traversal_ticks.load()) / double(tile_ticks) : 0;
  stats.seconds = timer.elapsed_s();
  return stats;
}

}  // namespace penumbra
