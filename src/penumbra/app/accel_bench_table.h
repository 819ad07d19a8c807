#pragma once
/// The results of `penumbra accel-bench`: one row per structure, with ray throughput at each
/// thread count, printed as one table and written as JSON.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::app {

/// Ray throughput at one thread count, in millions of rays per second.
struct BenchRates {
  int threads = 0;        ///< worker threads while tracing
  double primary = 0;     ///< closest hits of the pinhole camera's rays
  double incoherent = 0;  ///< closest hits of random rays
  double occlusion = 0;   ///< any hit of the same random rays
  double bounce = 0;      ///< closest hits of a path tracer's diffuse bounce rays (path_rays)
  double shadow = 0;      ///< any hit of its shadow rays, tmax short of the light
  /// Median over paired runs of this rate / Embree's (absent without Embree, and for Embree).
  std::optional<double> primary_vs_embree, incoherent_vs_embree, occlusion_vs_embree,
      bounce_vs_embree, shadow_vs_embree;
};

/// Node records visited and primitive tests per query of one ray set.
struct RayCounts {
  double nodes = 0, prims = 0;
};

/// The counts of the five ray sets (primary, incoherent, occlusion, bounce, shadow).
struct BenchCounts {
  RayCounts primary, incoherent, occlusion, bounce, shadow;
  /// The incoherent rays split by whether they hit something: their closest-hit and any-hit
  /// counts per ray over the rays that hit and over those that miss (zero for an empty group),
  /// and how many hit.
  RayCounts incoherent_hit, incoherent_miss, occlusion_hit, occlusion_miss;
  size_t incoherent_rays = 0, incoherent_hits = 0;
};

/// The measurements of one structure (or of Embree: "embree", or "embree:robust" in its robust
/// mode).
struct BenchRow {
  std::string accel;    ///< name with parameters, or "embree"
  std::string vectors;  ///< the code's instruction set (Accelerator::vectors()); empty for Embree
  double build_ms = 0;  ///< wall time of the build
  size_t bytes = 0;     ///< memory of the structure
  std::optional<size_t> nodes, depth;   ///< unknown for Embree
  std::optional<double> refs_per_prim;  ///< leaf references per primitive; unknown for Embree
  std::vector<BenchRates> rates;        ///< one per thread count, as the table's groups
  std::optional<size_t> mismatches;     ///< incoherent closest hits differing from Embree's
  std::optional<size_t> ties;           ///< of the agreeing ones, another triangle at the same t
  /// Per query of each ray set, counted by the structure (intersect_cost and occluded_cost in an
  /// untimed pass): node records visited and primitive tests. Unknown for Embree.
  std::optional<BenchCounts> counts;
  /// The structure's own figures (AccelStats::extra, e.g. the BVHs' "sah_cost").
  std::vector<std::pair<std::string, double>> extra;
};

/// One structure's throughput over another's in each ray set, at one thread count.
struct BenchOver {
  double primary = 0, incoherent = 0, occlusion = 0, bounce = 0, shadow = 0;
  /// From the two structures' ratios to Embree (each paired with Embree's runs, so that a load
  /// changing between the two structures' runs cancels), not from their rates.
  bool through_embree = false;
};

/// `a`'s throughput over `b`'s: the quotients of their ratios to Embree when both have them,
/// else of their rates.
BenchOver bench_over(const BenchRates& a, const BenchRates& b);

/// Prints the table: build ms (at `build_threads`), MiB, nodes, depth, refs/prim, then primary,
/// incoherent, occlusion, bounce and shadow Mrays/s and the incoherent ratio to Embree for each
/// thread count, then the ratios to Embree of the other four,
/// then the comparison of hits with Embree's; `repeat` runs gave each median. `batch`: the rates
/// are of batch queries against Embree's stream API (accel-bench --batch). With `versus` (a
/// row's name), also every other structure's throughput over that row's (bench_over).
void print_bench_table(const std::vector<BenchRow>& rows, int build_threads, int repeat,
                       bool batch = false, const std::string& versus = "");

/// Writes `rows` to `path` as a JSON array of objects (keys in docs/accel.md; `queries`:
/// "batch" or "single"; with `versus`, each other row's `versus` and its runs' `over_versus`);
/// throws Error when the file cannot be written.
void write_bench_json(const std::string& path, const std::vector<BenchRow>& rows,
                      const std::string& mesh, size_t triangles, int build_threads,
                      bool batch = false, const std::string& versus = "");

}  // namespace penumbra::app
