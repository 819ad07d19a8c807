#include "penumbra/app/render_command.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <mutex>
#include <tuple>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "penumbra/accel/registry.h"
#include "penumbra/app/cli_checks.h"
#include "penumbra/app/progress.h"
#include "penumbra/app/stats_format.h"
#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/params.h"
#include "penumbra/core/timer.h"
#include "penumbra/image/image_io.h"
#include "penumbra/render/filter/filter.h"
#include "penumbra/render/integrator/integrator_registry.h"
#include "penumbra/render/integrator/path_integrator.h"
#include "penumbra/render/render_job.h"
#include "penumbra/render/sampler/sampler_registry.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::app {

namespace {

/// " (8 paths at once)" when path shades in lanes, for the render's header line.
const char* lanes_note(const Integrator& integrator) {
  const auto* path = dynamic_cast<const PathIntegrator*>(&integrator);
  return path && path->uses_lanes() ? " (8 paths at once)" : "";
}

std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) {
  g_interrupted.store(true);
}

/// Installs the interrupt handler for SIGINT and SIGTERM while alive.
class InterruptGuard {
 public:
  InterruptGuard() {
    g_interrupted.store(false);
    old_int_ = std::signal(SIGINT, on_interrupt);
    old_term_ = std::signal(SIGTERM, on_interrupt);
  }
  ~InterruptGuard() {
    std::signal(SIGINT, old_int_);
    std::signal(SIGTERM, old_term_);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  void (*old_int_)(int);
  void (*old_term_)(int);
};

/// Parses "WxH".
std::pair<int, int> parse_resolution(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w <= 0 || h <= 0 || w > 65536 || h > 65536)
    throw Error(fmt::format("--resolution: expected WxH with 1..65536 each, got '{}'", text));
  return {w, h};
}

uint64_t parse_max_memory(const std::string& text) {
  try {
    return parse_memory_size(text);
  } catch (const Error& e) {
    throw Error(std::string("--max-memory: ") + e.what());
  }
}

const char* stop_text(StopReason r) {
  switch (r) {
    case StopReason::kTimeLimit:
      return "time limit";
    case StopReason::kTargetError:
      return "error target";
    case StopReason::kCancelled:
      return "interrupted";
    case StopReason::kComplete:
    default:
      return "complete";
  }
}

// Checks the names given by --accel, --integrator, --sampler and --filter, so that an error in
// them names the option (RenderJob names the scene file's "/render/..." for the rest).
void check_overrides(const RenderArgs& args) {
  const auto check = [](const char* option, const auto& make) {
    try {
      make();
    } catch (const Error& e) {
      throw Error(std::string(option) + ": " + e.what());
    }
  };
  if (args.accel) check("--accel", [&] { make_accelerator(*args.accel); });
  if (args.sampler) check("--sampler", [&] { make_sampler(*args.sampler, 1, 0); });
  if (args.filter) check("--filter", [&] { make_filter(*args.filter); });
  if (args.integrator) {
    check("--integrator", [&] {
      const std::string name = ParamList::parse(*args.integrator).name();
      std::string valid;
      for (const IntegratorInfo& i : integrator_list()) {
        if (i.name == name) return;
        valid += (valid.empty() ? "" : ", ") + i.name;
      }
      throw Error("unknown integrator '" + name + "' (valid: " + valid + ")");
    });
  }
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene file to an image");
  cmd->add_option("scene", args->scene, "Scene file (JSON; see docs/scene-format.md)")->required();
  cmd->add_option("-o,--output", args->output, "Output image: .png (8-bit sRGB), .exr or .pfm")
      ->required();
  cmd->add_option("--spp", args->spp,
                  "Samples per pixel (overrides the scene; the most a time- "
                  "or error-limited render takes)")
      ->transform(integer_in(1, 1 << 24));
  cmd->add_option("--threads", args->threads, "Worker threads (default: all cores)")
      ->transform(integer_in(1, 4096));
  cmd->add_option("--seed", args->seed, "Random seed (overrides the scene)")
      ->transform(unsigned_in(0, UINT64_MAX));
  cmd->add_option("--accel", args->accel, "Acceleration structure NAME[:params] (see accel-bench)");
  cmd->add_option("--integrator", args->integrator,
                  "Integrator NAME[:params]: raycast, whitted, distribution, path, photon, "
                  "sppm, radiosity (docs/rendering.md, photon-mapping.md, radiosity.md)");
  cmd->add_option("--sampler", args->sampler,
                  "Pixel sampler: independent (random), regular, jittered, sobol");
  cmd->add_option("--filter", args->filter,
                  "Pixel filter NAME[:params]: box, tent, gaussian, mitchell");
  cmd->add_option("--resolution", args->resolution, "Image size WxH (overrides the scene)");
  cmd->add_option("--max-depth", args->max_depth, "Maximum bounces (overrides the scene)")
      ->transform(integer_in(0, 1000000));
  cmd->add_option("--time-limit", args->time_limit,
                  "Stop after about this many seconds of rendering, keeping whole passes")
      ->check(positive_finite());
  cmd->add_option("--checkpoint", args->checkpoint,
                  "Write the image so far every this many seconds (atomically)")
      ->check(positive_finite());
  cmd->add_option("--target-error", args->target_error,
                  "Stop when the image's mean relative standard error falls below this")
      ->check(positive_finite());
  cmd->add_option("--variance", args->variance,
                  "Also write the per-pixel variance of the mean to this image (.exr or .pfm)");
  cmd->add_option("--max-memory", args->max_memory,
                  "Largest allocation sized by the input (film, photon map, form factors), as "
                  "16G, 800M, ... (default: three quarters of the machine's memory)");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress display or summary");
  cmd->callback([args] {
    const int code = run_render(*args);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

int run_render(const RenderArgs& args) {
  const Timer wall;
  // Reject bad output names and unwritable places before any work.
  image_format_for(args.output);
  check_writable(args.output);
  if (args.variance) {
    if (image_format_for(*args.variance) == ImageFormat::kPng)
      throw Error("--variance: the variance image needs a float format (.exr or .pfm), got '" +
                  *args.variance + "'");
    check_writable(*args.variance);
  }
  const ThreadLimit limit(args.threads.value_or(0));
  const ScopedMemoryLimit memory(args.max_memory ? parse_max_memory(*args.max_memory) : 0);

  SceneDesc desc = load_scene(args.scene);
  for (const std::string& w : desc.warnings) fmt::print(stderr, "warning: {}\n", w);
  RenderSettings& rs = desc.render;
  if (args.spp) rs.spp = *args.spp;
  if (args.seed) rs.seed = *args.seed;
  check_overrides(args);
  if (args.accel) rs.accel = *args.accel;
  if (args.integrator) rs.integrator = *args.integrator;
  if (args.sampler) rs.sampler = *args.sampler;
  if (args.filter) rs.filter = *args.filter;
  if (args.max_depth) rs.max_depth = *args.max_depth;
  if (args.resolution) {
    std::tie(rs.width, rs.height) = parse_resolution(*args.resolution);
    try {
      check_memory(Film::memory_bytes(rs.width, rs.height), "the film", "lower the resolution");
    } catch (const Error& e) {
      throw Error("--resolution " + *args.resolution + ": " + e.what());
    }
  }

  RenderJob job(std::move(desc));
  const RenderSettings& settings = job.scene.render;  // desc is moved from
  const AccelStats accel = job.world->accelerator().stats();
  if (!args.quiet)
    fmt::print(stderr,
               "{}: {} primitives, {} lights, {}{} {}x{} at {} spp ({}, {} filter), {} threads, "
               "accel {} built in {}\n",
               args.scene, job.world->primitives().size(), job.world->lights().size(),
               job.integrator->name(), lanes_note(*job.integrator), settings.width,
               settings.height, settings.spp,
               settings.sampler, job.filter->name(), thread_count(),
               job.world->accelerator().name(), format_duration(accel.build_ms * 1e-3));
  if (!args.quiet && job.world->has_instances()) {
    const InstanceBvh& top = job.world->instances();
    size_t object_prims = 0;
    for (const InstancedObject& o : top.objects()) object_prims += o.prims->size();
    fmt::print(stderr,
               "  {} instances of {} objects ({} primitives stored once), geometry and "
               "structures {:.1f} MiB\n",
               top.instances().size(), top.objects().size(), object_prims,
               double(job.world->geometry_bytes()) / (1024.0 * 1024.0));
  }

  // Sobol' with a power-of-two spp is progressive (every prefix of 2^k samples is a net);
  // stratified samplers and other spp are not.
  const bool power_of_two = (settings.spp & (settings.spp - 1)) == 0;
  const bool progressive = settings.sampler == "independent" || settings.sampler == "random" ||
                           (settings.sampler == "sobol" && power_of_two);
  if (!args.quiet && (args.time_limit || args.target_error) && !progressive)
    fmt::print(
        stderr,
        "note: sampler {} places its samples for {} spp; a render stopped early by time or "
        "error keeps a prefix of them (unbiased, less evenly spread). --sampler independent, "
        "or sobol with a power-of-two --spp, is progressive.\n",
        settings.sampler, settings.spp);
  RenderOptions& options = job.options;
  options.cancel = &g_interrupted;
  options.time_limit_s = args.time_limit.value_or(0.0);
  options.target_error = args.target_error.value_or(0.0);
  if (args.checkpoint) {
    options.checkpoint_s = *args.checkpoint;
    options.on_checkpoint = [&](const Film& film, int spp) {
      write_image(film.resolve(), args.output);
      if (!args.quiet) fmt::print(stderr, "\ncheckpoint: {} spp to {}\n", spp, args.output);
    };
  }
  options.on_warning = [](const std::string& m) { fmt::print(stderr, "warning: {}\n", m); };
  std::unique_ptr<RenderProgressLine> line;
  if (!args.quiet) {
    line = std::make_unique<RenderProgressLine>();
    options.on_progress = [&line](const RenderProgress& p) { line->update(p); };
    options.on_preprocess = [&line](const char* what, double f) { line->preprocess(what, f); };
  }

  RenderStats stats;
  {
    const InterruptGuard guard;
    stats = job.run();
  }
  if (line) line->finish();

  // Finished work is always written, atomically; an interrupted render says so and exits 130.
  write_image(job.film->resolve(), args.output);
  if (args.variance) write_image(job.film->variance(), *args.variance);
  if (!stats.complete()) {
    fmt::print(stderr,
               "interrupted: wrote {} spp to {} ({} of {} tiles also finished the next pass)\n",
               stats.spp_done, args.output, stats.tiles_done, stats.tiles_total);
    return 130;
  }
  if (!args.quiet) {
    const double secs = stats.seconds > 0 ? stats.seconds : 1e-9;
    const double samples =
        double(settings.width) * double(settings.height) * double(stats.spp_done);
    fmt::print(stderr, "wrote {} ({} spp of {}, {}{})\n", args.output, stats.spp_done,
               stats.spp_target, stop_text(stats.stop),
               stats.mean_rel_error >= 0
                   ? fmt::format(", mean relative error {:.4f}", stats.mean_rel_error)
                   : "");
    if (stats.preprocess_seconds > 0.01)
      fmt::print(stderr, "preprocess {}\n", format_duration(stats.preprocess_seconds));
    fmt::print(stderr,
               "render {}  (total {}), {} passes, {:.3f} Msamples/s, {} rays, {:.2f} Mrays/s, "
               "traversal {:.1f}% of tile time\n",
               format_duration(stats.seconds), format_duration(wall.elapsed_s()), stats.passes,
               samples / secs * 1e-6, stats.rays, double(stats.rays) / secs * 1e-6,
               stats.traversal_share * 100.0);
    fmt::print(stderr, "accel {} ({} code): {}\n", job.world->accelerator().name(),
               job.world->accelerator().vectors(), format_accel_stats(accel));
    if (!stats.note.empty()) fmt::print(stderr, "{}\n", stats.note);
  }
  return 0;
}

}  // namespace penumbra::app
