#include "penumbra/app/accel_bench.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include "penumbra/accel/registry.h"
#include "penumbra/app/accel_bench_table.h"
#include "penumbra/app/bench_rays.h"
#include "penumbra/app/cli_checks.h"
#include "penumbra/app/embree_scene.h"
#include "penumbra/app/mesh_check.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/target.h"
#include "penumbra/core/timer.h"
#include "penumbra/render/camera/camera_registry.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::app {

namespace {

/// Above this many triangles `all` leaves out brute (it would take hours).
constexpr size_t kBruteLimit = 100'000;
/// Seed of the incoherent ray set.
constexpr uint64_t kRaySeed = 0x5eed'acce'1be7ull;

/// The ray sets, with Embree's incoherent closest hits when it ran.
struct RaySets {
  std::vector<Ray> primary, incoherent;
  PathRays path;  ///< a path tracer's bounce and shadow rays from the primary hits
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

/// True when two closest hits differ: hit against miss, or t beyond 1e-4 relative.
bool differs(const Hit& a, const Hit& b) {
  if (a.valid() != b.valid()) return true;
  if (!a.valid()) return false;
  return std::fabs(a.t - b.t) > 1e-4f * std::max(std::fabs(a.t), std::fabs(b.t));
}

/// Sorted distinct thread counts of "1,all", "4", "1,2,8": `all` is `all_threads`.
std::vector<int> parse_thread_counts(const std::string& text, int all_threads) {
  std::vector<int> counts;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    int n = 0;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), n);
    if (item == "all")
      n = all_threads;
    else if (ec != std::errc() || ptr != item.data() + item.size() || n < 1 || n > 4096)
      throw Error(fmt::format(
          "--threads '{}': '{}' is not a thread count (1 to 4096, or 'all' for all cores)", text,
          item));
    counts.push_back(n);
    start = comma + 1;
  }
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  return counts;
}

/// Reads the rays [begin, begin + n) into the caches, as a renderer's rays are when it traces
/// them (made just before, in registers or L1).
void warm(const std::vector<Ray>& rays, size_t begin, size_t n) {
  float sum = 0;
  for (size_t i = begin; i < begin + n; ++i) sum += rays[i].tmin;
  asm volatile("" : : "r"(&sum), "x"(sum) : "memory");
}

/// Seconds to trace `rays` with `trace(first, last)` (the rays of indices [first, last)), in
/// chunks of kPairChunk rays; with `other`, each chunk is first traced with `other(first, last)`,
/// whose seconds go to `other_s`. Chunks alternate every 0.1-1 s, so both see the same load of a
/// shared machine; shorter chunks (16,384 rays) biased the ratio of a 70 MB structure by 8%, each
/// side starting with the caches filled by the other. Each side's chunk of rays is read into the
/// caches before it is timed: the side that went second used to find them there, and coherent
/// primary rays, whose traversal costs about as much as fetching the ray from memory, ran up to
/// 2x faster in that place.
constexpr size_t kPairChunk = 131072;
template <class F, class G>
double timed(const std::vector<Ray>& rays, const F& trace, const G* other, double& other_s) {
  double s = 0;
  for (size_t begin = 0; begin < rays.size(); begin += kPairChunk) {
    const size_t n = std::min(kPairChunk, rays.size() - begin);
    if (other) {
      warm(rays, begin, n);
      other_s +=
          time_chunks(n, [&](size_t b, size_t e) { (*other)(rays, begin + b, begin + e); });
    }
    warm(rays, begin, n);
    s += time_chunks(n, [&](size_t b, size_t e) { trace(rays, begin + b, begin + e); });
  }
  return s;
}

/// A side of the benchmark: its queries of one ray (closest(ray, hit), any(ray)) and of a batch
/// (closest_batch(rays, hits), any_batch(rays, blocked)); `batch` picks which are timed.
template <class Closest, class Any, class ClosestBatch, class AnyBatch>
struct Queries {
  Closest closest;
  Any any;
  ClosestBatch closest_batch;
  AnyBatch any_batch;
  bool batch = false;
};
template <class C, class A, class CB, class AB>
Queries<C, A, CB, AB> queries(C c, A a, CB cb, AB ab, bool batch) {
  return {c, a, cb, ab, batch};
}

/// Batch queries take kBenchBatch rays at a time, their answers in the caches (as a renderer's
/// would be) unless kept.
constexpr size_t kBenchBatch = 256;

/// One run of the ray sets through `side`'s queries at `threads` threads, the incoherent closest
/// hits going to `hits`; with `embree` given, interleaved chunk by chunk with Embree's, and the
/// ratios to it set.
template <class S, class E>
BenchRates run_once(const RaySets& rays, int threads, const S& side, std::vector<Hit>& hits,
                    const E* embree) {
  const ThreadLimit limit(threads);
  const bool pair = embree != nullptr;
  std::vector<Hit> embree_hits(pair ? hits.size() : 0);
  const auto mrays = [](size_t n, double s) { return double(n) / std::max(s, 1e-9) * 1e-6; };
  BenchRates rates;
  rates.threads = threads;
  // The timed functions of a side over the rays [b, e) of a set: one query at a time (the
  // loop the benchmark always had), or batches of kBenchBatch rays.
  const auto closest = [](const auto* q, Hit* keep) {
    return [q, keep](const std::vector<Ray>& r, size_t b, size_t e) {
      if (!q->batch && keep) {
        for (size_t i = b; i < e; ++i) q->closest(r[i], keep[i]);
        return;
      }
      if (!q->batch) {
        for (size_t i = b; i < e; ++i) {
          Hit h;
          q->closest(r[i], h);
        }
        return;
      }
      Hit own[kBenchBatch];
      for (size_t s = b; s < e; s += kBenchBatch) {
        const size_t n = std::min(kBenchBatch, e - s);
        q->closest_batch(std::span(r).subspan(s, n), std::span(keep ? keep + s : own, n));
      }
    };
  };
  const auto any = [](const auto* q) {
    return [q](const std::vector<Ray>& r, size_t b, size_t e) {
      if (!q->batch) {
        for (size_t i = b; i < e; ++i) q->any(r[i]);
        return;
      }
      uint8_t blocked[kBenchBatch];
      for (size_t s = b; s < e; s += kBenchBatch) {
        const size_t n = std::min(kBenchBatch, e - s);
        q->any_batch(std::span(r).subspan(s, n), std::span(blocked, n));
      }
    };
  };
  const auto primary = closest(&side, nullptr), incoherent = closest(&side, hits.data());
  const auto occlusion = any(&side);
  const auto embree_primary = closest(embree, nullptr);
  const auto embree_incoherent = closest(embree, embree_hits.data());
  const auto embree_occlusion = any(embree);
  const auto* ep_f = pair ? &embree_primary : nullptr;
  const auto* ei_f = pair ? &embree_incoherent : nullptr;
  const auto* eo_f = pair ? &embree_occlusion : nullptr;
  double ep = 0, ei = 0, eo = 0, eb = 0, es = 0;
  rates.primary = mrays(rays.primary.size(), timed(rays.primary, primary, ep_f, ep));
  // Fresh hits each run: a closest hit query starts from an empty record.
  std::fill(hits.begin(), hits.end(), Hit{});
  rates.incoherent = mrays(rays.incoherent.size(), timed(rays.incoherent, incoherent, ei_f, ei));
  rates.occlusion = mrays(rays.incoherent.size(), timed(rays.incoherent, occlusion, eo_f, eo));
  rates.bounce = mrays(rays.path.bounce.size(), timed(rays.path.bounce, primary, ep_f, eb));
  rates.shadow = mrays(rays.path.shadow.size(), timed(rays.path.shadow, occlusion, eo_f, es));
  if (pair) {
    rates.primary_vs_embree = rates.primary / mrays(rays.primary.size(), ep);
    rates.incoherent_vs_embree = rates.incoherent / mrays(rays.incoherent.size(), ei);
    rates.occlusion_vs_embree = rates.occlusion / mrays(rays.incoherent.size(), eo);
    rates.bounce_vs_embree = rates.bounce / mrays(rays.path.bounce.size(), eb);
    rates.shadow_vs_embree = rates.shadow / mrays(rays.path.shadow.size(), es);
  }
  return rates;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Measures a side (a structure, or Embree with no `embree`) `repeat` times at each thread
/// count: medians of the rates and, with `embree`, of the ratios to Embree over runs interleaved
/// with Embree's. Compares the incoherent closest hits with the reference if there is one, and
/// keeps them in `keep` if given.
template <class S, class E>
void measure(BenchRow& row, const RaySets& rays, const std::vector<int>& threads, int repeat,
             const S& side, const E* embree, std::vector<Hit>* keep) {
  std::vector<Hit> hits(rays.incoherent.size());
  for (const int t : threads) {
    std::vector<double> p, i, o, b, sh, pr, ir, orr, br, sr;
    for (int k = 0; k < repeat; ++k) {
      const BenchRates r = run_once(rays, t, side, hits, embree);
      p.push_back(r.primary), i.push_back(r.incoherent), o.push_back(r.occlusion);
      b.push_back(r.bounce), sh.push_back(r.shadow);
      if (r.incoherent_vs_embree)
        pr.push_back(*r.primary_vs_embree), ir.push_back(*r.incoherent_vs_embree),
            orr.push_back(*r.occlusion_vs_embree), br.push_back(*r.bounce_vs_embree),
            sr.push_back(*r.shadow_vs_embree);
    }
    BenchRates rates;
    rates.threads = t;
    rates.primary = median(p), rates.incoherent = median(i), rates.occlusion = median(o);
    rates.bounce = median(b), rates.shadow = median(sh);
    if (!ir.empty())
      rates.primary_vs_embree = median(pr), rates.incoherent_vs_embree = median(ir),
      rates.occlusion_vs_embree = median(orr), rates.bounce_vs_embree = median(br),
      rates.shadow_vs_embree = median(sr);
    row.rates.push_back(rates);
  }
  if (!rays.reference.empty()) {
    size_t mismatches = 0, ties = 0;
    for (size_t k = 0; k < hits.size(); ++k) {
      if (differs(hits[k], rays.reference[k]))
        ++mismatches;
      else if (hits[k].prim != rays.reference[k].prim)
        ++ties;
    }
    row.mismatches = mismatches, row.ties = ties;
  }
  if (keep) *keep = std::move(hits);
}

}  // namespace

void add_accel_bench_command(CLI::App& app) {
  auto args = std::make_shared<AccelBenchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "accel-bench", "Build acceleration structures over a mesh and measure ray throughput");
  cmd->add_option("input", args->input,
                  "Mesh (.obj, .ply) or scene (.json, .pbrt, .gltf, .glb: its meshes and quads as "
                  "triangles)")
      ->required();
  cmd->add_option("--accel", args->accels,
                  "Structures NAME[:params],... or 'all' (default; brute is left out of 'all' "
                  "above 100k triangles)");
  cmd->add_option("--threads", args->threads,
                  "Thread counts to trace with, comma-separated, 'all' = all cores (default "
                  "'1,all': one column group each); structures build with the largest");
  cmd->add_option("--json", args->json, "Also write the results to this JSON file");
  cmd->add_option("--rays", args->rays, "Incoherent (and occlusion) rays (default 1000000)")
      ->transform(integer_in(1, int64_t{1} << 30));
  cmd->add_option("--image", args->image,
                  "Side of the primary rays' square image, whose hits also start the bounce and "
                  "shadow rays (default 1024; a small one lets a profile see the other rays)")
      ->transform(integer_in(16, 4096));
  cmd->add_flag("--batch", args->batch,
               "Trace through the batch queries (intersect_batch, occluded_batch) against "
               "Embree's stream API (rtcIntersect1M, rtcOccluded1M; coherent for the primary "
               "rays) instead of single queries against rtcIntersect1 and rtcOccluded1");
  cmd->add_flag("--embree-robust", args->embree_robust,
                "Build Embree's scene with RTC_SCENE_FLAG_ROBUST (conservative box tests, "
                "watertight triangle test: our structures' guarantees) instead of its defaults; "
                "its row is then 'embree:robust'");
  cmd->add_option("--repeat", args->repeat,
                  "Runs per measurement (default 3): build times and rates are medians; each run "
                  "of a structure alternates with Embree's every 131072 rays, and 'x embree' is "
                  "the median ratio")
      ->transform(integer_in(1, 100));
  cmd->add_option("--versus", args->versus,
                  "A structure of --accel: also print every other one's throughput over its own, "
                  "from their paired ratios to Embree when it ran, else from the rates");
  cmd->callback([args] { run_accel_bench(*args); });
}

/// The rays of the scene's camera through the pixel centres of an image `width` pixels wide of the
/// scene's aspect ratio (lens centre, time 0).
std::vector<Ray> camera_rays(const SceneDesc& desc, int width) {
  const int height = std::clamp(
      int(std::lround(double(width) * desc.render.height / desc.render.width)), 1, 4 * width);
  const std::unique_ptr<Camera> camera = make_camera(desc.camera, width, height);
  std::vector<Ray> rays(size_t(width) * size_t(height));
  parallel_for(size_t(height), [&](size_t y) {
    for (int x = 0; x < width; ++x)
      rays[y * size_t(width) + size_t(x)] =
          camera->generate_ray({{float(x) + 0.5f, float(y) + 0.5f}, {0.5f, 0.5f}, 0.0f});
  });
  return rays;
}

/// The triangles of a scene in world space: meshes transformed, parallelograms as two triangles.
/// Spheres are left out (the benchmark and Embree's row measure triangles), with a note. The
/// triangles of emissive shapes are listed in `emitters`.
TriangleMesh scene_triangles(const SceneDesc& desc, std::vector<uint32_t>& emitters) {
  TriangleMesh out;
  size_t spheres = 0;
  bool emissive = false;
  auto add = [&](Vec3 a, Vec3 b, Vec3 c) {
    const auto base = static_cast<uint32_t>(out.positions.size());
    if (emissive) emitters.push_back(base / 3);
    out.positions.insert(out.positions.end(), {a, b, c});
    out.indices.insert(out.indices.end(), {base, base + 1, base + 2});
  };
  for (const ShapeDesc& shape : desc.shapes) {
    emissive = shape.emission && !shape.emission->is_black();
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
  if (!desc.instances.empty())
    fmt::print("note: {} instance(s) left out: accel-bench measures single-level structures\n",
               desc.instances.size());
  if (out.indices.empty()) throw Error(desc.file + ": the scene has no triangles to measure");
  return out;
}

void run_accel_bench(const AccelBenchArgs& args) {
  const std::vector<int> threads = parse_thread_counts(args.threads, thread_count());
  const int build_threads = threads.back();
  // Loading, ray generation and builds run on the largest thread count.
  std::optional<ThreadLimit> limit(std::in_place, build_threads);
  const Timer load_timer;
  // Scene files (JSON, pbrt, glTF) as scenes; everything else through the mesh reader.
  std::string ext = std::filesystem::path(args.input).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  const bool is_scene = ext == ".json" || ext == ".pbrt" || ext == ".gltf" || ext == ".glb";
  std::vector<std::string> warnings;
  std::vector<uint32_t> emitters;  // a scene's emissive triangles: the shadow rays' light
  std::vector<Ray> scene_camera;   // a scene's camera rays: where the path tracer's rays start
  const TriangleMesh mesh = [&] {
    if (!is_scene) return read_mesh(args.input, &warnings);
    const SceneDesc desc = load_scene(args.input);
    warnings = desc.warnings;
    scene_camera = camera_rays(desc, args.image);
    return scene_triangles(desc, emitters);
  }();
  print_warnings(warnings);
  check_mesh_input(mesh, args.input);
  PrimitiveSet prims;
  prims.add_mesh(mesh, Transform(), 0);
  fmt::print(
      "{}: {} triangles, loaded in {:.0f} ms; builds on {} thread(s), rays traced on {}; "
      "program compiled for {}\n",
      args.input, mesh.triangle_count(), load_timer.elapsed_ms(), build_threads,
      fmt::join(threads, " and "), compiled_vectors());

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
  // The code each structure runs (isa=: the build's own, or a level chosen when it runs).
  std::vector<std::string> codes;
  for (const auto& a : accels) codes.push_back(fmt::format("{} ({})", a->vectors(), a->name()));
  if (!codes.empty()) fmt::print("structures' code: {}\n", fmt::join(codes, ", "));
  // The --versus structure by the name its row will have.
  std::string versus;
  if (!args.versus.empty()) {
    try {
      versus = make_accelerator(args.versus)->name();
    } catch (const Error& e) {
      throw Error(fmt::format("--versus: {}", e.what()));
    }
    if (std::none_of(accels.begin(), accels.end(),
                     [&](const auto& a) { return a->name() == versus; }))
      throw Error(fmt::format("--versus {}: not one of the structures of --accel", args.versus));
  }

  RaySets rays;
  rays.primary = primary_rays(prims.bounds(), args.image, args.image);
  rays.incoherent = incoherent_rays(prims.bounds(), args.rays, kRaySeed);
  {
    // The path tracer's rays start at the primary hits, found with the default BVH.
    const std::unique_ptr<Accelerator> bvh = make_accelerator("bvh");
    bvh->build(prims);
    const std::vector<Ray>& camera = scene_camera.empty() ? rays.primary : scene_camera;
    std::vector<Hit> hits(camera.size());
    parallel_for(hits.size(), [&](size_t i) { bvh->intersect(camera[i], hits[i]); });
    rays.path = path_rays(prims, camera, hits, kRaySeed + 1, emitters);
  }
  fmt::print(
      "rays: {} primary ({}x{} pinhole), {} incoherent (closest hit), the same {} as "
      "occlusion queries with tmax = infinity; {} diffuse bounces and {} shadow rays (to {}) from "
      "the hits of {}\n",
      rays.primary.size(), args.image, args.image, rays.incoherent.size(), rays.incoherent.size(),
      rays.path.bounce.size(), rays.path.shadow.size(),
      emitters.empty() ? "a square light above the mesh" : "the scene's emitters",
      scene_camera.empty() ? "the primary rays" : "the scene camera's rays through pixel centres");

  // Each measurement sets its own thread limit: an enclosing one would cap it.
  limit.reset();
  std::vector<BenchRow> rows;
  const double triangles = double(mesh.triangle_count());
  std::optional<EmbreeScene> embree;
  // Single queries, or batch queries (--batch): ours against Embree's stream API, each side in
  // the mode that suits it on each set. Embree's coherent mode (packets sorted by octant) only
  // for the camera rays: on the path rays its incoherent mode is twice as fast (terrain bounce
  // rays 3.40 against 1.77 Mrays/s). Ours interleaves only the random rays: the camera rays in
  // pixel order, and the path rays starting at their hits, are coherent enough that their
  // neighbours find the same nodes in the caches (terrain bounce rays 2.99 one by one, 2.69
  // interleaved).
  const auto in = [](const Ray* r, const std::vector<Ray>& set) {
    return r >= set.data() && r < set.data() + set.size();
  };
  const auto coherent = [&](const Ray* r) { return in(r, rays.primary); };
  const auto order = [&](const Ray* r) {
    return in(r, rays.incoherent) ? BatchOrder::kIncoherent : BatchOrder::kCoherent;
  };
  const auto embree_side = queries(
      [&](const Ray& r, Hit& h) { embree->intersect(r, h); },
      [&](const Ray& r) { embree->occluded(r); },
      [&](std::span<const Ray> r, std::span<Hit> h) {
        embree->intersect_stream(r, h, coherent(r.data()));
      },
      [&](std::span<const Ray> r, std::span<uint8_t> out) {
        embree->occluded_stream(r, out, coherent(r.data()));
      },
      args.batch);
  using ES = decltype(embree_side);
  if (have_embree()) {
    BenchRow row;
    row.accel = "embree";
    {
      const ThreadLimit build_limit(build_threads);
      std::vector<double> ms;
      for (int k = 0; k < args.repeat; ++k) {
        embree.reset();  // each build from the same state: the previous one's memory freed
        embree.emplace(mesh, build_threads, args.embree_robust);
        ms.push_back(embree->build_ms());
      }
      row.build_ms = median(ms);
    }
    if (embree->robust()) row.accel = "embree:robust";  // as Embree reports its mode
    row.bytes = embree->bytes();
    measure(row, rays, threads, args.repeat, embree_side, static_cast<const ES*>(nullptr),
            &rays.reference);
    rows.push_back(row);
  }
  for (size_t a = 0; a < accels.size(); ++a) {
    auto& accel = accels[a];
    BenchRow row;
    row.accel = accel->name();
    row.vectors = accel->vectors();
    {
      const ThreadLimit build_limit(build_threads);
      std::vector<double> ms;
      for (int k = 0; k < args.repeat; ++k) {
        if (k) accel = make_accelerator(specs[a]);  // a fresh structure, the last one freed
        const Timer timer;
        accel->build(prims);
        ms.push_back(timer.elapsed_ms());
      }
      row.build_ms = median(ms);
    }
    const AccelStats st = accel->stats();
    row.bytes = st.bytes, row.nodes = st.nodes, row.depth = st.max_depth;
    row.refs_per_prim = double(st.prim_refs) / triangles;
    row.extra = st.extra;
    const auto side = queries(
        [&](const Ray& r, Hit& h) { accel->intersect(r, h); },
        [&](const Ray& r) { accel->occluded(r); },
        [&](std::span<const Ray> r, std::span<Hit> h) {
          accel->intersect_batch(r, h, order(r.data()));
        },
        [&](std::span<const Ray> r, std::span<uint8_t> out) {
          accel->occluded_batch(r, out, order(r.data()));
        },
        args.batch);
    measure(row, rays, threads, args.repeat, side, embree ? &embree_side : nullptr, nullptr);
    // The structure's own counts over each ray set (a separate, untimed pass), and whether
    // each closest-hit query found a hit.
    const auto costs_of = [&](const std::vector<Ray>& set, bool any_hit,
                              std::vector<uint8_t>* hits = nullptr) {
      std::vector<TraversalCost> costs(set.size());
      if (hits) hits->assign(set.size(), 0);
      parallel_for(costs.size(), [&](size_t i) {
        Hit h;
        if (any_hit) {
          accel->occluded_cost(set[i], costs[i]);
        } else {
          const bool hit = accel->intersect_cost(set[i], h, costs[i]);
          if (hits) (*hits)[i] = hit;
        }
      });
      return costs;
    };
    // The mean over the queries whose hit flag is `want` (every query when `hits` is null).
    const auto mean = [](const std::vector<TraversalCost>& costs,
                         const std::vector<uint8_t>* hits = nullptr, uint8_t want = 1) {
      TraversalCost total;
      size_t n = 0;
      for (size_t i = 0; i < costs.size(); ++i)
        if (!hits || (*hits)[i] == want) total += costs[i], ++n;
      const double d = double(std::max<size_t>(1, n));
      return RayCounts{double(total.nodes) / d, double(total.prims) / d};
    };
    std::vector<uint8_t> hits;
    const auto incoherent = costs_of(rays.incoherent, false, &hits);
    const auto occlusion = costs_of(rays.incoherent, true);
    BenchCounts c;
    c.primary = mean(costs_of(rays.primary, false));
    c.incoherent = mean(incoherent), c.occlusion = mean(occlusion);
    c.bounce = mean(costs_of(rays.path.bounce, false));
    c.shadow = mean(costs_of(rays.path.shadow, true));
    c.incoherent_hit = mean(incoherent, &hits, 1), c.incoherent_miss = mean(incoherent, &hits, 0);
    c.occlusion_hit = mean(occlusion, &hits, 1), c.occlusion_miss = mean(occlusion, &hits, 0);
    c.incoherent_rays = hits.size();
    c.incoherent_hits = size_t(std::count(hits.begin(), hits.end(), uint8_t(1)));
    row.counts = c;
    rows.push_back(row);
    accel.reset();  // free its memory before the next build
  }
  print_bench_table(rows, build_threads, args.repeat, args.batch, versus);
  if (!args.json.empty())
    write_bench_json(args.json, rows, args.input, mesh.triangle_count(), build_threads, args.batch,
                     versus);
}

}  // namespace penumbra::app
