#pragma once
/// `penumbra accel-bench`: builds acceleration structures over a mesh and measures build time,
/// memory and ray throughput on deterministic ray sets, optionally against Embree 3.
#include <cstddef>
#include <string>

namespace CLI {
class App;
}

namespace penumbra::app {

/// The options of one benchmark run.
struct AccelBenchArgs {
  std::string input;              ///< mesh (.obj, .ply) or scene (.json, not yet supported)
  std::string accels = "all";     ///< comma-separated NAME[:params], or "all"
  std::string threads = "1,all";  ///< thread counts to trace with: N,... or "all" (all cores)
  std::string json;               ///< when set, results are also written here as a JSON array
  size_t rays = 1'000'000;        ///< incoherent (and occlusion) rays
  /// Side of the primary rays' square image (its width for a scene's camera). The path
  /// tracer's rays start at its hits, so it sets their number too; a small image leaves the
  /// incoherent rays most of a profile's samples.
  int image = 1024;
  /// Runs per measurement: rates are medians; with Embree, each run of a structure alternates
  /// with one of Embree's chunk by chunk (131,072 rays), and the ratios are the medians over runs
  /// (robust to the load of a shared machine changing during the benchmark).
  int repeat = 3;
  /// Trace through the batch queries against Embree's stream API (--batch).
  bool batch = false;
  /// Build Embree's scene in its robust mode (--embree-robust): the same guarantees as ours
  /// (no ray through a shared edge, no box missed by rounding) instead of Embree's defaults.
  bool embree_robust = false;
  /// A structure of `accels` (as named there, e.g. "kdtree"): every other one's throughput is
  /// also printed over its own (--versus).
  std::string versus;
};

/// Registers the `accel-bench` subcommand on `app`.
void add_accel_bench_command(CLI::App& app);

/// Runs the benchmark, printing a table to stdout; throws Error on bad input. Structures build
/// once, with the largest thread count, and trace each ray set at every thread count.
void run_accel_bench(const AccelBenchArgs& args);

}  // namespace penumbra::app
