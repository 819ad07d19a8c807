#include "penumbra/app/radiosity_command.h"

#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "penumbra/app/cli_checks.h"
#include "penumbra/app/progress.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"
#include "penumbra/render/radiosity/radiosity_integrator.h"
#include "penumbra/render/radiosity/radiosity_solution.h"
#include "penumbra/render/render_job.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::app {

namespace {

struct RadiosityArgs {
  std::string scene, output;
  std::optional<std::string> integrator;
  std::optional<int> threads;
  bool quiet = false;
};

int run_radiosity(const RadiosityArgs& args) {
  const Timer wall;
  if (args.output.size() < 4 || args.output.substr(args.output.size() - 4) != ".ply")
    throw Error("radiosity: the solution is written as PLY: '" + args.output +
                "' does not end in .ply");
  const ThreadLimit limit(args.threads.value_or(0));
  SceneDesc desc = load_scene(args.scene);
  for (const std::string& w : desc.warnings) fmt::print(stderr, "warning: {}\n", w);
  // The scene's radiosity parameters, or the defaults, or --integrator's.
  if (args.integrator) {
    desc.render.integrator = *args.integrator;
  } else if (desc.render.integrator.rfind("radiosity", 0) != 0) {
    desc.render.integrator = "radiosity";
  }
  if (desc.render.integrator.rfind("radiosity", 0) != 0)
    throw Error("radiosity: --integrator must name radiosity (with its parameters), got '" +
                desc.render.integrator + "'");
  RenderJob job(std::move(desc));
  job.options.on_warning = [](const std::string& m) { fmt::print(stderr, "warning: {}\n", m); };
  auto& integrator = dynamic_cast<RadiosityIntegrator&>(*job.integrator);
  if (!args.quiet) fmt::print(stderr, "{}: {}\n", args.scene, integrator.name());
  integrator.solve(job);
  write_radiosity_solution(args.output, integrator.mesh(), integrator.corner_radiosity(),
                           args.scene + ", " + integrator.name());
  if (!args.quiet) {
    const RadiosityReport& r = integrator.report();
    fmt::print(stderr, "{} elements, mesh {}\n", r.elements, format_duration(r.mesh_seconds));
    if (!r.round_elements.empty()) {
      std::string rounds;
      for (const size_t n : r.round_elements) rounds += fmt::format(" {}", n);
      fmt::print(stderr, "adaptive subdivision: elements after each round:{}\n", rounds);
    }
    if (r.links > 0)
      fmt::print(stderr,
                 "hierarchy: {} top-level patches, {} clusters, {} nodes ({} leaves), {} links, "
                 "{:.1f} MiB, solve {} (linking {}, gathering {}: {} iterations)\n",
                 r.top_patches, r.clusters, r.nodes, r.leaves, r.links,
                 double(r.hierarchy_bytes) / (1 << 20), format_duration(r.solve_seconds),
                 format_duration(r.refine_seconds), format_duration(r.gather_seconds),
                 r.iterations);
    else
      fmt::print(stderr,
                 "form factors {} ({:.1f} MiB; row sums {:.4f}..{:.4f}, reciprocity error "
                 "{:.4f}), solve {} ({} iterations, residual {:.2e})\n",
                 format_duration(r.form_factor_seconds), double(r.matrix_bytes) / (1 << 20),
                 r.min_row_sum, r.max_row_sum, r.reciprocity_error,
                 format_duration(r.solve_seconds), r.iterations,
                 r.residuals.empty() ? 0.0 : r.residuals.back());
    if (!r.residuals.empty()) {
      std::string line;
      for (double v : r.residuals) line += fmt::format(" {:.2e}", v);
      fmt::print(stderr, "{} per iteration:{}\n", r.links > 0 ? "change" : "residual", line);
    }
    fmt::print(stderr, "wrote {} (total {})\n", args.output, format_duration(wall.elapsed_s()));
  }
  return 0;
}

}  // namespace

void add_radiosity_command(CLI::App& app) {
  auto args = std::make_shared<RadiosityArgs>();
  CLI::App* cmd = app.add_subcommand(
      "radiosity",
      "Solve a scene's radiosity and write the solved mesh as PLY (per-vertex colour)");
  cmd->add_option("scene", args->scene, "Scene file (.json)")->required();
  cmd->add_option("-o,--output", args->output, "The solution (.ply)")->required();
  cmd->add_option("--integrator", args->integrator,
                  "radiosity[:params] (patch, form_factors, rays, resolution, solver, tolerance, "
                  "hierarchy, epsilon, clusters; see docs/radiosity.md)");
  cmd->add_option("--threads", args->threads, "Worker threads (default: all cores)")
      ->transform(integer_in(1, 4096));
  cmd->add_flag("-q,--quiet", args->quiet, "No report");
  cmd->callback([args] {
    const int code = run_radiosity(*args);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace penumbra::app
