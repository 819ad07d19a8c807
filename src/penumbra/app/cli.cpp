#include "penumbra/app/cli.h"

#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "penumbra/app/accel_bench.h"
#include "penumbra/app/bsp2d_command.h"
#include "penumbra/app/collide_command.h"
#include "penumbra/app/convert_command.h"
#include "penumbra/app/radiosity_command.h"
#include "penumbra/app/render_command.h"
#include "penumbra/core/error.h"

namespace penumbra::app {

int run_cli(int argc, char** argv) {
  CLI::App app{"penumbra: an offline renderer and a laboratory of spatial data structures for ray "
               "shooting"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "penumbra 0.1.0");
  add_render_command(app);
  add_accel_bench_command(app);
  add_collide_command(app);
  add_bsp2d_command(app);
  add_radiosity_command(app);
  add_convert_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    // Every error of the program ends here: one message, a non-zero exit.
    fmt::print(stderr, "penumbra: error: {}\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace penumbra::app
