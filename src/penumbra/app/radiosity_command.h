#pragma once
/// `penumbra radiosity`: solves a scene's radiosity and writes the solved mesh (view-independent)
/// as a PLY with per-vertex colours, for mesh viewers and for renders that reuse it.
namespace CLI {
class App;
}

namespace penumbra::app {

/// Registers the `radiosity` subcommand on `app`.
void add_radiosity_command(CLI::App& app);

}  // namespace penumbra::app
