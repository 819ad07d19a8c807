#include "penumbra/app/render_command.h"

#include <atomic>
#include <csignal>
#include <tuple>
#include <cstdio>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "penumbra/accel/registry.h"
#include "penumbra/app/progress.h"
#include "penumbra/app/stats_format.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"
#include "penumbra/image/image_io.h"
#include "penumbra/render/camera/camera_registry.h"
#include "penumbra/render/integrator/integrator_registry.h"
#include "penumbra/render/renderer.h"
#include "penumbra/render/filter/filter.h"
#include "penumbra/render/sampler/sampler_registry.h"
#include "penumbra/render/world.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::app {

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) { g_interrupted.store(true); }

/// Parses "WxH".
std::pair<int, int> parse_resolution(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w <= 0 || h <= 0 || w > 65536 || h > 65536)
    throw Error(fmt::format("--resolution: expected WxH with 1..65536 each, got '{}'", text));
  return {w, h};
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene file to an image");
  cmd->add_option("scene", args->scene, "Scene file (JSON; see docs/scene-format.md)")->required();
  cmd->add_option("-o,--output", args->output, "Output image: .png (8-bit sRGB), .exr or .pfm")
      ->required();
  cmd->add_option("--spp", args->spp, "Samples per pixel (overrides the scene)")
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--threads", args->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--seed", args->seed, "Random seed (overrides the scene)");
  cmd->add_option("--accel", args->accel, "Acceleration structure NAME[:params] (see accel-bench)");
  cmd->add_option("--integrator", args->integrator, "Integrator NAME[:params]: raycast, whitted");
  cmd->add_option("--sampler", args->sampler,
                  "Pixel sampler: independent (random), regular, jittered, sobol");
  cmd->add_option("--filter", args->filter,
                  "Pixel filter NAME[:params]: box, tent, gaussian, mitchell");
  cmd->add_option("--resolution", args->resolution, "Image size WxH (overrides the scene)");
  cmd->add_option("--max-depth", args->max_depth, "Maximum bounces (overrides the scene)")
      ->check(CLI::Range(0, 1000));
  cmd->add_flag("-q,--quiet", args->quiet, "No progress display or summary");
  cmd->callback([args] {
    const int code = run_render(*args);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

int run_render(const RenderArgs& args) {
  const Timer wall;
  image_format_for(args.output);  // reject a bad output name before any work
  const ThreadLimit limit(args.threads.value_or(0));

  SceneDesc desc = load_scene(args.scene);
  RenderSettings& rs = desc.render;
  if (args.spp) rs.spp = *args.spp;
  if (args.seed) rs.seed = *args.seed;
  if (args.accel) rs.accel = *args.accel;
  if (args.integrator) rs.integrator = *args.integrator;
  if (args.sampler) rs.sampler = *args.sampler;
  if (args.filter) rs.filter = *args.filter;
  if (args.max_depth) rs.max_depth = *args.max_depth;
  if (args.resolution) std::tie(rs.width, rs.height) = parse_resolution(*args.resolution);

  const World world(desc, rs.accel);
  const auto camera = make_camera(desc.camera, rs.width, rs.height);
  const auto integrator = make_integrator(rs.integrator, world, rs);
  const auto sampler = make_sampler(rs.sampler, rs.spp, rs.seed);
  const auto filter = make_filter(rs.filter);
  const FilterSampler filter_sampler(*filter);
  const AccelStats accel = world.accelerator().stats();
  if (!args.quiet)
    fmt::print(stderr, "{}: {} primitives, {} {}x{} at {} spp ({}, {} filter), {} threads, accel {} built in {}\n",
               args.scene, world.primitives().size(), integrator->name(), rs.width, rs.height,
               rs.spp, rs.sampler, filter->name(), thread_count(), world.accelerator().name(),
               format_duration(accel.build_ms * 1e-3));

  Film film(rs.width, rs.height);
  RenderOptions options;
  options.cancel = &g_interrupted;
  g_interrupted.store(false);
  std::unique_ptr<Progress> bar;
  if (!args.quiet) {
    const size_t tiles = size_t((rs.width + options.tile_size - 1) / options.tile_size) *
                         size_t((rs.height + options.tile_size - 1) / options.tile_size);
    bar = std::make_unique<Progress>("render", tiles);
    options.on_tile = [&bar](size_t done, size_t) { bar->update(done); };
  }
  const auto old_handler = std::signal(SIGINT, on_interrupt);
  const RenderStats stats = render(*camera, *integrator, *sampler, filter_sampler, film, options);
  std::signal(SIGINT, old_handler);
  if (bar) bar->finish();

  // Finished work is always written, atomically; an interrupted render says so and exits 130.
  write_image(film.resolve(), args.output);
  if (!stats.complete()) {
    fmt::print(stderr, "interrupted: wrote {} of {} tiles to {}\n", stats.tiles_done,
               stats.tiles_total, args.output);
    return 130;
  }
  if (!args.quiet) {
    fmt::print(stderr, "wrote {}\n", args.output);
    fmt::print(stderr, "render {}  (total {}), {} rays, {:.2f} Mrays/s\n",
               format_duration(stats.seconds), format_duration(wall.elapsed_s()), stats.rays,
               stats.seconds > 0 ? double(stats.rays) / stats.seconds * 1e-6 : 0.0);
    fmt::print(stderr, "accel {}: {}\n", world.accelerator().name(), format_accel_stats(accel));
  }
  return 0;
}

}  // namespace penumbra::app
