#pragma once
/// The command-line interface: subcommands render, accel-bench and collide.

namespace penumbra::app {

/// Runs the CLI; returns the process exit code. Every error is caught here, printed, and turned
/// into a non-zero exit.
int run_cli(int argc, char** argv);

}  // namespace penumbra::app
