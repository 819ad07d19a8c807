#pragma once
/// `penumbra convert`: reads a scene in any format penumbra loads (JSON, pbrt-v4, and what the
/// scene loader adds) and writes it as a JSON scene with its meshes as PLY files beside it.
#include <string>

namespace CLI {
class App;
}

namespace penumbra::app {

/// What `penumbra convert` was asked to do.
struct ConvertArgs {
  std::string input;     ///< the scene to read
  std::string output;    ///< the JSON scene to write (must end in .json)
  std::string mesh_dir;  ///< the meshes' folder, relative to the output's; "" = "<stem>-meshes"
  bool quiet = false;    ///< no summary line
};

/// Registers the `convert` subcommand.
void add_convert_command(CLI::App& app);

/// Runs a conversion; throws Error (InputError for a bad scene) without writing anything when the
/// input cannot be read or an output cannot be written.
void run_convert(const ConvertArgs& args);

}  // namespace penumbra::app
