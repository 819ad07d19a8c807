/// Build time per triangle of every registered structure on the benchmark terrain
/// (bench/terrain.h) from 10^4 to 10^7 triangles: the O(N log N) curve. Not a Google Benchmark
/// loop: each structure builds at each size (the median of 3 builds below 10^6 triangles, one
/// above) until a build takes longer than `--budget` seconds (default 20; the next size would
/// take about ten times as long) or the structure refuses the size (its own memory caps). With
/// Embree built in, `embree` (Embree 3's default build of the same triangles, as accel-bench
/// times it) is measured too, the reference of issue #19's build target. Prints one table and,
/// with --json FILE, writes the rows (bench/plot_build_scaling.py draws them).
///   build/build_scaling [--threads N] [--budget S] [--accel a,b,...] [--json FILE]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "penumbra/accel/registry.h"
#include "penumbra/app/embree_scene.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"
#include "terrain.h"

namespace {

/// Minor page faults of the process so far: each is a fresh page (4 KiB, or 2 MiB where huge
/// pages were granted) touched for the first time, which on some virtual machines costs
/// microseconds: a build that faults in tens of thousands of pages spends much of its time there.
long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

using namespace penumbra;

struct Row {
  std::string accel;
  size_t triangles;
  double ms;
};

// Vertices per side giving about 10^4, 10^5, 10^6 and 10^7 triangles.
constexpr int kSides[] = {72, 225, 708, 2237};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= s.size()) {
    const size_t comma = std::min(s.find(',', start), s.size());
    if (comma > start) out.push_back(s.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 1;
  double budget_s = 20;
  std::string json, accels;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    if (a == "--threads" && more) {
      threads = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--budget" && more) {
      budget_s = std::atof(argv[++i]);
    } else if (a == "--json" && more) {
      json = argv[++i];
    } else if (a == "--accel" && more) {
      accels = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--threads N] [--budget S] [--accel a,b] [--json FILE]\n",
                   argv[0]);
      return 2;
    }
  }
  std::vector<std::string> names;
  if (accels.empty()) {
    for (const auto& info : accelerator_list())
      if (info.name != "brute") names.push_back(info.name);  // brute has no build to measure
    if (app::have_embree()) names.emplace_back("embree");
  } else {
    names = split(accels);
  }
  for (const std::string& name : names) {
    if (name == "embree" && !app::have_embree()) {
      std::fprintf(stderr, "embree: not built in (install Embree 3 and rebuild)\n");
      return 2;
    }
    if (name != "embree") {
      try {
        make_accelerator(name);  // an unknown name or parameter before any build
      } catch (const Error& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
      }
    }
  }
  const ThreadLimit limit(threads);
  std::vector<Row> rows;
  std::vector<bool> stopped(names.size(), false);
  std::printf("terrain builds at %d thread(s); ns/tri and ns/(tri log2 N)\n", threads);
  std::printf("%-14s %10s %10s %8s %12s %10s\n", "accel", "triangles", "build ms", "ns/tri",
              "ns/(t log N)", "faults");
  for (const int side : kSides) {
    const TriangleMesh mesh = bench::terrain(side);
    PrimitiveSet prims;
    prims.add_mesh(mesh, Transform(), 0);
    const size_t n = prims.size();
    for (size_t k = 0; k < names.size(); ++k) {
      if (stopped[k]) continue;
      const int builds = n < 1'000'000 ? 3 : 1;
      std::vector<double> ms;
      long faults = 0;
      try {
        for (int b = 0; b < builds; ++b) {
          const long f0 = minor_faults();
          if (names[k] == "embree") {
            // Its own wall time of buffers, geometry and commit, as accel-bench reports it.
            const app::EmbreeScene scene(mesh, threads);
            ms.push_back(scene.build_ms());
          } else {
            auto accel = make_accelerator(names[k]);
            const Timer t;
            accel->build(prims);
            ms.push_back(t.elapsed_ms());
          }
          faults = minor_faults() - f0;  // the last build's
        }
      } catch (const Error& e) {  // a structure's own limit (bsp's fragment cap): noted, skipped
        std::printf("%-14s %10zu refused: %s\n", names[k].c_str(), n, e.what());
        stopped[k] = true;
        continue;
      }
      std::sort(ms.begin(), ms.end());
      const double m = ms[ms.size() / 2], per = m * 1e6 / double(n);
      std::printf("%-14s %10zu %10.1f %8.1f %12.2f %10ld\n", names[k].c_str(), n, m, per,
                  per / std::log2(double(n)), faults);
      std::fflush(stdout);
      rows.push_back({names[k], n, m});
      if (m > budget_s * 1000) stopped[k] = true;
    }
  }
  if (!json.empty()) {
    std::ofstream out(json);
    out << "[\n";
    for (size_t i = 0; i < rows.size(); ++i)
      out << "  {\"accel\": \"" << rows[i].accel << "\", \"triangles\": " << rows[i].triangles
          << ", \"build_ms\": " << rows[i].ms << ", \"threads\": " << threads << "}"
          << (i + 1 < rows.size() ? ",\n" : "\n");
    out << "]\n";
  }
  return 0;
}
