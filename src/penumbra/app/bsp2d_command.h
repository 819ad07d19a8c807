#pragma once
/// `penumbra bsp2d`: the 2D laboratory. Builds a structure (BSP of segments, object BSP, quadtree,
/// kd-tree, grid) over segments read from a file or generated, prints its size, shoots one ray and
/// prints the hit and the traversal path in the lecture's notation, and draws it all as SVG; or
/// runs the fragment experiment (bsp2d_experiment.h). See docs/lab2d.md.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace penumbra::app {

/// The options of one bsp2d run.
struct Bsp2DArgs {
  std::string input;                 ///< segment file (docs/lab2d.md), or empty with --random
  std::optional<size_t> random;      ///< generate this many random disjoint segments
  std::string structure = "bsp";     ///< NAME[:params] of accel2d/registry2d.h
  std::optional<std::string> order;  ///< bsp only: random | first | fewest-cuts
  uint64_t seed = 1;                 ///< the random order's seed and the generator's
  std::optional<std::string> ray;    ///< "x,y,dx,dy"; else the file's ray, else a default one
  std::string svg;                   ///< when set, the picture is written here
  std::string experiment;            ///< "fragments": run the experiment instead
  size_t max_n = 100'000;            ///< experiment: largest n
  size_t seeds = 3;                  ///< experiment: seeds per n
};

/// Registers the `bsp2d` subcommand on `app`.
void add_bsp2d_command(CLI::App& app);

/// Runs one bsp2d invocation, printing to stdout; throws Error on bad input.
void run_bsp2d(const Bsp2DArgs& args);

}  // namespace penumbra::app
