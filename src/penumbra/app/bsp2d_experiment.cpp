#include "penumbra/app/bsp2d_experiment.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <vector>

#include <fmt/format.h>

#include "penumbra/accel2d/random_segments.h"
#include "penumbra/accel2d/segment_bsp.h"
#include "penumbra/app/svg2d.h"
#include "penumbra/core/timer.h"

namespace penumbra::app {

namespace {

using lab2d::BspOrder;

/// Each build is repeated until this much time has passed and its fastest run kept: a single
/// 20 µs build is mostly noise, and the minimum is the figure least disturbed by other processes.
constexpr double kMinTimingMs = 20.0;

/// CPU time of this thread in milliseconds. Builds are timed in CPU time, not wall time: on a
/// shared machine a build longer than a scheduler slice is preempted on every run, which adds
/// other processes' time to the wall clock (measured here: a step of 3x in the wall-clock figure
/// between n = 7,000 and 10,000 under a load of 11 on 2 cores, absent in CPU time).
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// One row of the table: means over the seeds.
struct Row {
  std::string input;
  BspOrder order;
  size_t n = 0, seeds = 0;
  double fragments = 0, nodes = 0, depth = 0, build_ms = 0;
  double per_nlogn() const { return fragments / (double(n) * std::log(double(n))); }
  double ns_per_nlog2n() const {
    const double l = std::log2(double(n));
    return build_ms * 1e6 / (double(n) * l * l);
  }
};

/// Builds the BSP of `scene` with `order` and `seed`; adds its figures (divided by `runs`) to row.
void measure(const lab2d::Scene2D& scene, BspOrder order, uint64_t seed, Row& row, double runs) {
  lab2d::SegmentBsp bsp(order, seed);
  double fastest = INFINITY;
  const Timer timer;
  do {
    const double start = thread_cpu_ms();
    bsp.build(scene);
    fastest = std::min(fastest, thread_cpu_ms() - start);
  } while (timer.elapsed_ms() < kMinTimingMs);
  const lab2d::Stats2D st = bsp.stats();
  row.fragments += double(st.fragments) / runs;
  row.nodes += double(st.nodes) / runs;
  row.depth += double(st.depth) / runs;
  row.build_ms += fastest / runs;
}

void print_row(const Row& r) {
  fmt::print("{:<8} {:<12} {:>7} {:>5} {:>11.1f} {:>9.3f} {:>11.1f} {:>7.1f} {:>10.3f} {:>9.2f}\n",
             r.input, lab2d::to_string(r.order), r.n, r.seeds, r.fragments, r.per_nlogn(), r.nodes,
             r.depth, r.build_ms, r.ns_per_nlog2n());
  std::fflush(stdout);
}

}  // namespace

void run_fragment_experiment(size_t max_n, size_t seeds, const std::string& svg_path) {
  fmt::print(
      "2DRANDOMBSP on random disjoint segments (lengths 0.25..1 in a square of side sqrt(n)), and\n"
      "the first-segment order on the comb (docs/lab2d.md); means over the seeds of the fastest "
      "of\n"
      "repeated builds, in CPU time.\n"
      "frag/nln = fragments / (n ln n); ns/nlog2 = build ns / (n log2(n)^2)\n\n");
  fmt::print("{:<8} {:<12} {:>7} {:>5} {:>11} {:>9} {:>11} {:>7} {:>10} {:>9}\n", "input", "order",
             "n", "seeds", "fragments", "frag/nln", "nodes", "depth", "build ms", "ns/nlog2");
  std::vector<Row> rows;
  const size_t sizes[] = {100, 300, 1000, 3000, 10000, 30000, 100000, 300000, 1000000};
  for (size_t n : sizes) {
    if (n > max_n) break;
    Row row{"random", BspOrder::kRandom, n, seeds};
    for (uint64_t seed = 1; seed <= seeds; ++seed)
      measure(lab2d::random_segments(n, seed), BspOrder::kRandom, seed, row, double(seeds));
    print_row(row);
    rows.push_back(row);
  }
  // The comb: the first-segment order is quadratic (and its build cubic), so n stops at 1000.
  for (size_t n : {100, 300, 1000}) {
    if (n > max_n) break;
    const lab2d::Scene2D comb = lab2d::comb_segments(n);
    Row first{"comb", BspOrder::kFirst, n, 1};
    measure(comb, BspOrder::kFirst, 1, first, 1);
    Row random{"comb", BspOrder::kRandom, n, seeds};
    for (uint64_t seed = 1; seed <= seeds; ++seed)
      measure(comb, BspOrder::kRandom, seed, random, double(seeds));
    print_row(first);
    print_row(random);
    rows.push_back(first);
    rows.push_back(random);
  }
  if (svg_path.empty()) return;

  // The plot: the two normalised figures of 2DRANDOMBSP, and the comb's fragments per segment.
  auto series = [&](const char* input, BspOrder order, const char* name, auto value) {
    PlotSeries s{name, {}};
    for (const Row& r : rows)
      if (r.input == input && r.order == order) s.points.push_back({double(r.n), value(r)});
    return s;
  };
  const auto per_nlogn = [](const Row& r) { return r.per_nlogn(); };
  const auto per_n = [](const Row& r) { return r.fragments / double(r.n); };
  const auto time = [](const Row& r) { return r.ns_per_nlog2n(); };
  const std::vector<PlotPanel> panels = {
      {"Fragments / (n ln n) of 2DRANDOMBSP: bounded (Theorem: E[fragments] = O(n log n))",
       "n (segments)",
       "fragments / (n ln n)",
       {series("random", BspOrder::kRandom, "random segments", per_nlogn),
        series("comb", BspOrder::kRandom, "comb, random order", per_nlogn)}},
      {"Build time / (n log2² n): flat for random segments (expected O(n log² n)); the comb is n "
       "deep",
       "n (segments)",
       "ns / (n log2² n)",
       {series("random", BspOrder::kRandom, "random segments", time),
        series("comb", BspOrder::kRandom, "comb, random order", time)}},
      {"The comb: fragments per segment, first-segment order against random order",
       "n (segments)",
       "fragments / n",
       {series("comb", BspOrder::kFirst, "first order", per_n),
        series("comb", BspOrder::kRandom, "random order", per_n)}},
  };
  write_text_atomically(svg_path, svg_of_plot(panels));
  fmt::print("\nplot: {}\n", svg_path);
}

}  // namespace penumbra::app
