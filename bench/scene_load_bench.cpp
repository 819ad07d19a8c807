/// Google Benchmark: how fast scenes load. The pbrt-v4 reader on a text `trianglemesh` of 200k
/// triangles (bytes per second), and a 1M-triangle mesh read as a PLY file alone next to the
/// same file through a pbrt `plymesh` scene (the pbrt layer's own cost), and a quad PLY (the
/// polygon triangulator's cost). Files are generated in a temporary folder; timings are for
/// comparison within one run.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "penumbra/scene/ply_reader.h"
#include "penumbra/scene/ply_writer.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

/// A folder for the generated files, removed at exit.
const fs::path& folder() {
  static const struct Dir {
    fs::path path =
        fs::temp_directory_path() / ("penumbra-load-bench-" + std::to_string(::getpid()));
    Dir() { fs::create_directories(path); }
    ~Dir() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  } dir;
  return dir.path;
}

/// A wavy grid of n x n quads (2 n^2 triangles).
TriangleMesh grid(int n) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.positions.push_back(
          {i / float(n), 0.05f * float((i * 7 + j * 3) % 11) / 11.0f, j / float(n)});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      for (uint32_t k : {a, c, b, b, c, d}) m.indices.push_back(k);
    }
  return m;
}

/// The pbrt scene with the mesh as a text trianglemesh.
const std::string& text_scene() {
  static const std::string path = [] {
    const TriangleMesh m = grid(316);  // 199,712 triangles
    std::string s = "WorldBegin\nShape \"trianglemesh\"\n  \"point3 P\" [\n";
    for (Vec3 p : m.positions)
      s += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    s += "]\n  \"integer indices\" [\n";
    for (size_t i = 0; i < m.indices.size(); i += 3)
      s += std::to_string(m.indices[i]) + " " + std::to_string(m.indices[i + 1]) + " " +
           std::to_string(m.indices[i + 2]) + "\n";
    s += "]\n";
    const std::string p = (folder() / "text.pbrt").string();
    std::ofstream(p, std::ios::binary) << s;
    return p;
  }();
  return path;
}

/// The 1M-triangle PLY file and a pbrt scene that names it.
const std::string& ply_file() {
  static const std::string path = [] {
    const std::string p = (folder() / "mesh.ply").string();
    std::ofstream(p, std::ios::binary) << encode_ply(grid(708));  // 1,002,528 triangles
    std::ofstream(folder() / "ply.pbrt")
        << "WorldBegin\nShape \"plymesh\" \"string filename\" \"mesh.ply\"\n";
    return p;
  }();
  return path;
}

/// A smooth height field of 708 x 708 = 501,264 quads (binary little-endian; 1,002,528
/// triangles): PLY polygons go through the polygon triangulator (its convexity test, then the
/// fan). (grid()'s quads are far from planar, their heights jump by 35 cells.)
const std::string& quad_ply_file() {
  static const std::string path = [] {
    const int n = 708;
    TriangleMesh m = grid(n);
    for (Vec3& p : m.positions)
      p.y = 0.05f * std::sin(6.2831853f * p.x) * std::cos(6.2831853f * p.z);
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                    std::to_string(m.positions.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(n * n) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
    for (Vec3 p : m.positions) s.append(reinterpret_cast<const char*>(&p), sizeof p);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int32_t a = j * (n + 1) + i, quad[4] = {a, a + n + 1, a + n + 2, a + 1};
        s += char(4);
        s.append(reinterpret_cast<const char*>(quad), sizeof quad);
      }
    const std::string p = (folder() / "quads.ply").string();
    std::ofstream(p, std::ios::binary) << s;
    return p;
  }();
  return path;
}

void BM_PbrtTextTriangles(benchmark::State& state) {
  const std::string& path = text_scene();
  for (auto _ : state) benchmark::DoNotOptimize(load_scene(path));
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(fs::file_size(path)));
}
BENCHMARK(BM_PbrtTextTriangles)->Unit(benchmark::kMillisecond);

void BM_PlyAlone1M(benchmark::State& state) {
  const std::string& path = ply_file();
  for (auto _ : state) benchmark::DoNotOptimize(read_ply(path));
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(fs::file_size(path)));
}
BENCHMARK(BM_PlyAlone1M)->Unit(benchmark::kMillisecond);

void BM_PlyQuads1M(benchmark::State& state) {
  const std::string& path = quad_ply_file();
  for (auto _ : state) benchmark::DoNotOptimize(read_ply(path));
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(fs::file_size(path)));
}
BENCHMARK(BM_PlyQuads1M)->Unit(benchmark::kMillisecond);

void BM_PbrtPlymesh1M(benchmark::State& state) {
  ply_file();
  const std::string path = (folder() / "ply.pbrt").string();
  for (auto _ : state) benchmark::DoNotOptimize(load_scene(path));
}
BENCHMARK(BM_PbrtPlymesh1M)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
