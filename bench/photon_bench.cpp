/// Google Benchmark of photon mapping on the bundled scenes (Cornell box, caustic scene):
/// photons traced per second at 1 and 2 threads, the photon map's kd-tree build time and bytes
/// per photon, and density-estimate query time at k = 100. Timings are for comparison within
/// one run; run with --benchmark_repetitions=5 for medians.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/photon/photon_map.h"
#include "penumbra/render/photon/photon_tracer.h"
#include "penumbra/render/world.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

const char* const kScenes[] = {"cornell-box.json", "caustic.json"};

/// The world of bundled scene i, built once.
const World& world(int i) {
  static std::map<int, std::unique_ptr<World>> worlds;
  auto& w = worlds[i];
  if (!w) {
    const SceneDesc desc = load_scene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + kScenes[i]);
    w = std::make_unique<World>(desc, desc.render.accel);
  }
  return *w;
}

/// Photons traced per second (all hits stored): arg 0 the scene, arg 1 the threads.
void BM_TracePhotons(benchmark::State& state) {
  const World& w = world(int(state.range(0)));
  const ThreadLimit limit(int(state.range(1)));
  const PhotonTracer tracer(w, -1);
  constexpr uint64_t kPhotons = 200000;
  uint64_t seed = 0, rays = 0, stored = 0;
  for (auto _ : state) {
    const PhotonBatch b = tracer.trace_batch(kPhotons, ++seed, PhotonStore::kAll);
    rays += b.rays;
    stored += b.photons.size();
    benchmark::DoNotOptimize(b.photons.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations() * kPhotons));
  state.counters["photons/s"] =
      benchmark::Counter(double(state.iterations() * kPhotons), benchmark::Counter::kIsRate);
  state.counters["rays/photon"] = double(rays) / double(state.iterations() * kPhotons);
  state.counters["stored/photon"] = double(stored) / double(state.iterations() * kPhotons);
  state.SetLabel(kScenes[state.range(0)]);
}
BENCHMARK(BM_TracePhotons)
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// A global map of the Cornell box from 10^6 photons (about 2.6 million stored).
const std::vector<Photon>& cornell_photons() {
  static const std::vector<Photon> photons =
      PhotonTracer(world(0), -1).trace_batch(1000000, 7, PhotonStore::kAll).photons;
  return photons;
}

/// Building the photon map's kd-tree over the Cornell box's photons.
void BM_BuildPhotonMap(benchmark::State& state) {
  const std::vector<Photon>& photons = cornell_photons();
  size_t bytes = 0;
  for (auto _ : state) {
    PhotonMap map(photons);
    bytes = map.bytes();
    benchmark::DoNotOptimize(&map);
  }
  state.counters["photons"] = double(photons.size());
  state.counters["bytes/photon"] = double(bytes) / double(photons.size());
  state.counters["Mphotons/s"] = benchmark::Counter(
      double(state.iterations() * photons.size()) * 1e-6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BuildPhotonMap)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Irradiance estimates (k = 100 nearest, restricted to the surface) at the stored photons'
/// own positions, on one thread.
void BM_IrradianceQuery(benchmark::State& state) {
  const std::vector<Photon>& photons = cornell_photons();
  static const PhotonMap map(photons);
  DensityQuery q;
  q.k = int(state.range(0));
  q.max_radius = 0.05f * length(world(0).bounds().diagonal());
  std::vector<KdNeighbor> scratch;
  Pcg32 rng(5);
  Rgb sum;
  for (auto _ : state) {
    const Photon& p = photons[rng.next_bounded(uint32_t(photons.size()))];
    sum += map.irradiance(p.p, p.incident(), q, scratch);
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_IrradianceQuery)->Arg(50)->Arg(100)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
