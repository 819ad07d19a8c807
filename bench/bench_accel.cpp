/// Google Benchmark: build time and single-ray throughput (closest hit, occlusion) of the
/// registered BVHs (bvh, bvh4, bvh8) over a generated 180k-triangle bumpy torus and incoherent
/// rays, and the binned SAH split search alone on nodes of 16 to 65,536 references (the inner
/// loop of the build; items are references). Timings are for comparison within one run.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "penumbra/accel/build/binned_sah.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/rng.h"

namespace penumbra {
namespace {

/// A bumpy torus of 2 * 300 * 300 triangles (rotated, so nothing is axis-aligned).
const PrimitiveSet& mesh() {
  static const PrimitiveSet prims = [] {
    TriangleMesh m;
    const int rings = 300, sides = 300;
    const float two_pi = 2.0f * std::numbers::pi_v<float>;
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < sides; ++j) {
        const float u = two_pi * float(i) / float(rings), v = two_pi * float(j) / float(sides);
        const float r = 0.35f + 0.05f * std::sin(7.0f * u) * std::cos(5.0f * v);
        m.positions.push_back({(1.0f + r * std::cos(v)) * std::cos(u),
                               (1.0f + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
      }
    const auto at = [&](int a, int b) { return uint32_t((a % rings) * sides + (b % sides)); };
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < sides; ++j)
        for (uint32_t k :
             {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)})
          m.indices.push_back(k);
    PrimitiveSet p;
    p.add_mesh(m, rotate(25.0f, Vec3(1, 2, 3)), 0);
    return p;
  }();
  return prims;
}

/// 65536 rays with origins uniform in the bounds and uniform directions (fixed seed).
const std::vector<Ray>& rays() {
  static const std::vector<Ray> out = [] {
    std::vector<Ray> r(1 << 16);
    Pcg32 rng(1234, 5);
    const Bounds3 b = mesh().bounds();
    for (Ray& ray : r) {
      ray.o = b.lo + b.diagonal() * Vec3(rng.next_float(), rng.next_float(), rng.next_float());
      const float z = 1.0f - 2.0f * rng.next_float(), s = std::sqrt(std::max(0.0f, 1 - z * z));
      const float phi = 2.0f * std::numbers::pi_v<float> * rng.next_float();
      ray.d = {s * std::cos(phi), s * std::sin(phi), z};
    }
    return r;
  }();
  return out;
}

void build(benchmark::State& state, const std::string& spec) {
  for (auto _ : state) {
    auto accel = make_accelerator(spec);
    accel->build(mesh());
    benchmark::DoNotOptimize(accel.get());
  }
  state.counters["triangles"] = double(mesh().size());
}

void closest_hit(benchmark::State& state, const std::string& spec) {
  auto accel = make_accelerator(spec);
  accel->build(mesh());
  size_t hits = 0;
  for (auto _ : state)
    for (const Ray& r : rays()) {
      Hit h;
      hits += accel->intersect(r, h);
    }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays().size()));
}

void occlusion(benchmark::State& state, const std::string& spec) {
  auto accel = make_accelerator(spec);
  accel->build(mesh());
  size_t hits = 0;
  for (auto _ : state)
    for (const Ray& r : rays()) hits += accel->occluded(r);
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays().size()));
}

/// find_binned_split over `state.range(0)` consecutive references of the torus (neighbours in
/// id order are neighbours on the surface, as in a node deep in a tree), 16 bins or fewer as the
/// builder uses them, blocks of four.
void binned_split(benchmark::State& state) {
  static const PrimRefs refs = make_prim_refs(mesh());
  const auto n = size_t(state.range(0));
  const std::span<const PrimRef> node(refs.refs.data() + refs.refs.size() / 3, n);
  Bounds3 centroids;
  for (const PrimRef& r : node) centroids.extend(r.centroid2());
  const BinMapping map(centroids, std::min(16, std::max(4, int(n))));
  for (auto _ : state) benchmark::DoNotOptimize(find_binned_split(node, map, false, 2).cost);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(n));
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  using namespace penumbra;
  for (const auto& info : accelerator_list()) {
    if (info.name.rfind("bvh", 0) != 0) continue;  // the BVH family (bvh, bvh4, bvh8)
    benchmark::RegisterBenchmark(("build/" + info.name).c_str(), build, info.name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("closest_hit/" + info.name).c_str(), closest_hit, info.name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("occlusion/" + info.name).c_str(), occlusion, info.name)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("binned_split", binned_split)
      ->RangeMultiplier(4)
      ->Range(16, 1 << 16);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
