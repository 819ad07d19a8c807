#pragma once
/// `penumbra render`: renders a scene file to an image.
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace penumbra::app {

/// The options of one render; unset optionals keep the scene file's value.
struct RenderArgs {
  std::string scene;
  std::string output;
  std::optional<int> spp, threads, max_depth;
  std::optional<uint64_t> seed;
  std::optional<std::string> accel, integrator, sampler, filter, resolution;
  std::optional<double> time_limit, checkpoint, target_error;
  std::optional<std::string> variance;    ///< where to write the per-pixel variance image
  std::optional<std::string> max_memory;  ///< the memory limit, as "16G" (core/memory_limit.h)
  bool quiet = false;
};

/// Registers the `render` subcommand on `app`.
void add_render_command(CLI::App& app);

/// Runs a render; returns the exit code (0, or 130 when interrupted after writing finished work).
int run_render(const RenderArgs& args);

}  // namespace penumbra::app
