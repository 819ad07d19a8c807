#include "penumbra/app/accel_bench.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "penumbra/accel/registry.h"
#include "penumbra/app/bench_rays.h"
#include "penumbra/app/embree_scene.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::app {

namespace {

/// Above this many triangles `all` leaves out brute (it would take hours).
constexpr size_t kBruteLimit = 100'000;
/// Side of the square primary-ray image.
constexpr int kImageSide = 1024;
/// Seed of the incoherent ray set.
constexpr uint64_t kRaySeed = 0x5eed'acce'1be7ull;

/// One row of the result table.
struct Row {
  std::string accel;
  double build_ms = 0;
  size_t bytes = 0, nodes = 0, depth = 0;
  double primary = 0, incoherent = 0, occlusion = 0;  ///< Mrays/s
  std::optional<size_t> mismatches, ties;             ///< closest hits against Embree
};

/// The ray sets, with Embree's incoherent closest hits when it ran.
struct RaySets {
  std::vector<Ray> primary, incoherent;
  std::vector<Hit> reference;
};

/// Splits "bvh,bvh:leaf=4,bins=8,brute" into structures. Parameters contain commas too, so an
/// item starts a new structure when the previous one has no parameters or when the text before
/// its ':' is a registered name; otherwise it continues the previous structure's parameters.
std::vector<std::string> split_accels(const std::string& text) {
  const auto registered = [](const std::string& name) {
    for (const auto& info : accelerator_list())
      if (info.name == name) return true;
    return false;
  };
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    if (item.empty()) throw Error(fmt::format("--accel '{}': empty item", text));
    const std::string head = item.substr(0, item.find(':'));
    if (out.empty() || out.back().find(':') == std::string::npos || registered(head))
      out.push_back(item);
    else
      out.back() += "," + item;
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

/// Mrays/s of tracing `rays` with `trace(ray)`.
template <class F>
double throughput(const std::vector<Ray>& rays, const F& trace) {
  const double s = time_chunks(rays.size(), [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) trace(rays[i], i);
  });
  return double(rays.size()) / std::max(s, 1e-9) * 1e-6;
}

/// True when two closest hits differ: hit against miss, or t beyond 1e-4 relative.
bool differs(const Hit& a, const Hit& b) {
  if (a.valid() != b.valid()) return true;
  if (!a.valid()) return false;
  return std::fabs(a.t - b.t) > 1e-4f * std::max(std::fabs(a.t), std::fabs(b.t));
}

/// Runs the three ray sets through `intersect` and `occluded`, comparing with the reference.
template <class Intersect, class Occluded>
void measure(Row& row, const RaySets& rays, const Intersect& intersect, const Occluded& occluded,
             std::vector<Hit>* keep) {
  row.primary = throughput(rays.primary, [&](const Ray& r, size_t) {
    Hit h;
    intersect(r, h);
  });
  std::vector<Hit> hits(rays.incoherent.size());
  row.incoherent =
      throughput(rays.incoherent, [&](const Ray& r, size_t i) { intersect(r, hits[i]); });
  row.occlusion = throughput(rays.incoherent, [&](const Ray& r, size_t) { occluded(r); });
  if (!rays.reference.empty()) {
    size_t mismatches = 0, ties = 0;
    for (size_t i = 0; i < hits.size(); ++i) {
      if (differs(hits[i], rays.reference[i]))
        ++mismatches;
      else if (hits[i].prim != rays.reference[i].prim)
        ++ties;
    }
    row.mismatches = mismatches, row.ties = ties;
  }
  if (keep) *keep = std::move(hits);
}

void print_table(const std::vector<Row>& rows) {
  fmt::print("{:<22} {:>10} {:>10} {:>10} {:>6} {:>10} {:>10} {:>10} {:>12}\n", "accel", "build ms",
             "MiB", "nodes", "depth", "primary", "incoher.", "occlusion", "vs embree");
  for (const Row& r : rows) {
    const std::string cmp =
        r.mismatches ? fmt::format("{} ({} ties)", *r.mismatches, *r.ties) : "-";
    // Embree reports neither nodes nor depth.
    const bool shape = r.accel != "embree";
    fmt::print("{:<22} {:>10.1f} {:>10.1f} {:>10} {:>6} {:>10.2f} {:>10.2f} {:>10.2f} {:>12}\n",
               r.accel, r.build_ms, double(r.bytes) / (1 << 20),
               shape ? std::to_string(r.nodes) : "-", shape ? std::to_string(r.depth) : "-",
               r.primary, r.incoherent, r.occlusion, cmp);
  }
  fmt::print(
      "(Mrays/s; 'vs embree': incoherent closest hits differing from Embree's, hit vs miss "
      "or t beyond 1e-4 relative; ties: same t, another triangle)\n");
}

void write_json(const std::string& path, const std::vector<Row>& rows, const std::string& mesh,
                size_t triangles, int threads) {
  nlohmann::json out = nlohmann::json::array();
  for (const Row& r : rows) {
    nlohmann::json o = {{"accel", r.accel},
                        {"threads", threads},
                        {"build_ms", r.build_ms},
                        {"bytes", r.bytes},
                        {"nodes", r.nodes},
                        {"depth", r.depth},
                        {"primary_mrays", r.primary},
                        {"incoherent_mrays", r.incoherent},
                        {"occlusion_mrays", r.occlusion},
                        {"triangles", triangles},
                        {"mesh", mesh}};
    if (r.mismatches) o["embree_mismatches"] = *r.mismatches;
    out.push_back(o);
  }
  std::ofstream f(path);
  f << out.dump(2) << "\n";
  if (!f) throw Error(fmt::format("{}: cannot write", path));
}

}  // namespace

void add_accel_bench_command(CLI::App& app) {
  auto args = std::make_shared<AccelBenchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "accel-bench", "Build acceleration structures over a mesh and measure ray throughput");
  cmd->add_option("input", args->input,
                  "Mesh (.obj, .ply) or scene (.json: its meshes and quads as triangles)")
      ->required();
  cmd->add_option("--accel", args->accels,
                  "Structures NAME[:params],... or 'all' (default; brute is left out of 'all' "
                  "above 100k triangles)");
  cmd->add_option("--threads", args->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--json", args->json, "Also write the results to this JSON file");
  cmd->add_option("--rays", args->rays, "Incoherent (and occlusion) rays (default 1000000)")
      ->check(CLI::Range(size_t(1), size_t(1) << 30));
  cmd->callback([args] { run_accel_bench(*args); });
}

/// The triangles of a scene in world space: meshes transformed, parallelograms as two triangles.
/// Spheres are left out (the benchmark and Embree's row measure triangles), with a note.
TriangleMesh scene_triangles(const SceneDesc& desc) {
  TriangleMesh out;
  size_t spheres = 0;
  auto add = [&out](Vec3 a, Vec3 b, Vec3 c) {
    const auto base = static_cast<uint32_t>(out.positions.size());
    out.positions.insert(out.positions.end(), {a, b, c});
    out.indices.insert(out.indices.end(), {base, base + 1, base + 2});
  };
  for (const ShapeDesc& shape : desc.shapes) {
    const Transform& m = shape.to_world;
    if (const auto* mesh = std::get_if<TriangleMesh>(&shape.geometry)) {
      for (size_t t = 0; t < mesh->triangle_count(); ++t)
        add(m.point(mesh->positions[mesh->indices[3 * t]]),
            m.point(mesh->positions[mesh->indices[3 * t + 1]]),
            m.point(mesh->positions[mesh->indices[3 * t + 2]]));
    } else if (const auto* q = std::get_if<QuadData>(&shape.geometry)) {
      const Vec3 p = m.point(q->p), p1 = m.point(q->p + q->e1), p2 = m.point(q->p + q->e2),
                 p3 = m.point(q->p + q->e1 + q->e2);
      add(p, p1, p3);
      add(p, p3, p2);
    } else {
      ++spheres;
    }
  }
  if (spheres) fmt::print("note: {} sphere(s) left out: accel-bench measures triangles\n", spheres);
  if (out.indices.empty()) throw Error(desc.file + ": the scene has no triangles to measure");
  return out;
}

void run_accel_bench(const AccelBenchArgs& args) {
  const ThreadLimit limit(args.threads);
  const int threads = thread_count();
  const Timer load_timer;
  const bool is_scene =
      args.input.size() >= 5 && args.input.substr(args.input.size() - 5) == ".json";
  const TriangleMesh mesh =
      is_scene ? scene_triangles(load_scene(args.input)) : read_mesh(args.input);
  PrimitiveSet prims;
  prims.add_mesh(mesh, Transform(), 0);
  fmt::print("{}: {} triangles, loaded in {:.0f} ms; {} thread(s)\n", args.input,
             mesh.triangle_count(), load_timer.elapsed_ms(), threads);

  // Structures to run: explicit names, or every registered one.
  std::vector<std::string> specs;
  if (args.accels == "all") {
    for (const auto& info : accelerator_list()) {
      if (info.name == "brute" && mesh.triangle_count() > kBruteLimit) {
        fmt::print("note: brute left out above {} triangles (name it to run it)\n", kBruteLimit);
        continue;
      }
      specs.push_back(info.name);
    }
  } else {
    specs = split_accels(args.accels);
  }
  std::vector<std::unique_ptr<Accelerator>> accels;
  for (const auto& s : specs) accels.push_back(make_accelerator(s));  // reject bad names first

  RaySets rays;
  rays.primary = primary_rays(prims.bounds(), kImageSide, kImageSide);
  rays.incoherent = incoherent_rays(prims.bounds(), args.rays, kRaySeed);
  fmt::print(
      "rays: {} primary ({}x{} pinhole), {} incoherent (closest hit), the same {} as "
      "occlusion queries with tmax = infinity\n",
      rays.primary.size(), kImageSide, kImageSide, rays.incoherent.size(), rays.incoherent.size());

  std::vector<Row> rows;
  if (have_embree()) {
    const EmbreeScene embree(mesh, args.threads);
    Row row;
    row.accel = "embree", row.build_ms = embree.build_ms(), row.bytes = embree.bytes();
    measure(
        row, rays, [&](const Ray& r, Hit& h) { return embree.intersect(r, h); },
        [&](const Ray& r) { return embree.occluded(r); }, &rays.reference);
    rows.push_back(row);
  }
  for (auto& accel : accels) {
    Row row;
    row.accel = accel->name();
    const Timer timer;
    accel->build(prims);
    row.build_ms = timer.elapsed_ms();
    const AccelStats st = accel->stats();
    row.bytes = st.bytes, row.nodes = st.nodes, row.depth = st.max_depth;
    measure(
        row, rays, [&](const Ray& r, Hit& h) { return accel->intersect(r, h); },
        [&](const Ray& r) { return accel->occluded(r); }, nullptr);
    rows.push_back(row);
    accel.reset();  // free its memory before the next build
  }
  print_table(rows);
  if (!args.json.empty()) write_json(args.json, rows, args.input, mesh.triangle_count(), threads);
}

}  // namespace penumbra::app
