/// Google Benchmark: build time, k-nearest (k = 50) and fixed-radius query times of the balanced
/// point kd-tree over uniform random photon-like records (28 bytes), with the bytes per point as
/// a counter. Timings are for comparison within one run.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <vector>

#include "penumbra/accel/point_kdtree.h"
#include "penumbra/core/rng.h"

namespace penumbra {
namespace {

/// The size and shape of a stored photon: position, packed direction, power.
struct BenchPhoton {
  Vec3 p;
  uint32_t dir = 0;
  float power[3] = {0, 0, 0};
};
static_assert(sizeof(BenchPhoton) == 28);

Vec3 random_in_cube(Pcg32& rng) {
  return {rng.next_float() * 2 - 1, rng.next_float() * 2 - 1, rng.next_float() * 2 - 1};
}

std::vector<BenchPhoton> photons(size_t n) {
  Pcg32 rng(n, 3);
  std::vector<BenchPhoton> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = {random_in_cube(rng), uint32_t(i), {1, 1, 1}};
  return v;
}

/// One tree per size, built on first use and kept for the query benchmarks.
const PointKdTree<BenchPhoton>& tree(size_t n) {
  static std::map<size_t, PointKdTree<BenchPhoton>> trees;
  auto it = trees.find(n);
  if (it == trees.end()) it = trees.emplace(n, PointKdTree<BenchPhoton>(photons(n))).first;
  return it->second;
}

std::vector<Vec3> queries() {
  Pcg32 rng(99, 5);
  std::vector<Vec3> q(4096);
  for (Vec3& v : q) v = random_in_cube(rng);
  return q;
}

void BM_Build(benchmark::State& state) {
  const std::vector<BenchPhoton> input = photons(size_t(state.range(0)));
  size_t bytes = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<BenchPhoton> copy = input;  // the build takes its records
    state.ResumeTiming();
    const PointKdTree<BenchPhoton> t(std::move(copy));
    bytes = t.bytes();
    benchmark::DoNotOptimize(t.points().data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0));
  state.counters["bytes_per_point"] = double(bytes) / double(state.range(0));
}
BENCHMARK(BM_Build)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

void BM_Nearest50(benchmark::State& state) {
  const PointKdTree<BenchPhoton>& t = tree(size_t(state.range(0)));
  const std::vector<Vec3> qs = queries();
  std::vector<KdNeighbor> out;
  out.reserve(50);
  size_t i = 0, found = 0;
  for (auto _ : state) {
    found += t.nearest(qs[i++ & 4095], 50, INFINITY, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
  state.counters["found"] = double(found) / double(state.iterations());
  state.counters["bytes_per_point"] = double(t.bytes()) / double(t.size());
}
BENCHMARK(BM_Nearest50)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);

/// Radius holding 50 points on average: (4/3) pi r^3 = 8 * 50 / N for the cube [-1, 1]^3.
void BM_Radius(benchmark::State& state) {
  const auto n = size_t(state.range(0));
  const PointKdTree<BenchPhoton>& t = tree(n);
  const std::vector<Vec3> qs = queries();
  const float r = float(std::cbrt(8.0 * 50.0 / double(n) * 3.0 / (4.0 * std::numbers::pi)));
  size_t i = 0, found = 0;
  for (auto _ : state) {
    float sum = 0;
    t.for_each_in_radius(qs[i++ & 4095], r * r, [&](const BenchPhoton& ph, float) {
      sum += ph.power[0];
      ++found;
    });
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
  state.counters["found"] = double(found) / double(state.iterations());
}
BENCHMARK(BM_Radius)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
