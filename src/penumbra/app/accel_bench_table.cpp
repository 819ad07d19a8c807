#include "penumbra/app/accel_bench_table.h"

#include <algorithm>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "penumbra/core/error.h"
#include "penumbra/core/target.h"
#include "penumbra/image/image_io.h"

namespace penumbra::app {

namespace {

/// Width of a throughput column, and of a group of six with their separators.
constexpr int kRateWidth = 8;
constexpr int kGroupWidth = 6 * (kRateWidth + 1);

std::string thread_label(int threads) {
  return fmt::format("{} thread{}", threads, threads == 1 ? "" : "s");
}

template <class T>
std::string or_dash(const std::optional<T>& v, const char* format) {
  return v ? fmt::format(fmt::runtime(format), *v) : "-";
}

/// The row named `name`, or null.
const BenchRow* find_row(const std::vector<BenchRow>& rows, const std::string& name) {
  for (const BenchRow& r : rows)
    if (r.accel == name) return &r;
  return nullptr;
}

}  // namespace

BenchOver bench_over(const BenchRates& a, const BenchRates& b) {
  BenchOver o;
  o.through_embree = a.incoherent_vs_embree && b.incoherent_vs_embree;
  const auto q = [&](double x, double y, const std::optional<double>& xe,
                     const std::optional<double>& ye) {
    if (o.through_embree) return *xe / *ye;
    return y > 0 ? x / y : 0.0;
  };
  o.primary = q(a.primary, b.primary, a.primary_vs_embree, b.primary_vs_embree);
  o.incoherent = q(a.incoherent, b.incoherent, a.incoherent_vs_embree, b.incoherent_vs_embree);
  o.occlusion = q(a.occlusion, b.occlusion, a.occlusion_vs_embree, b.occlusion_vs_embree);
  o.bounce = q(a.bounce, b.bounce, a.bounce_vs_embree, b.bounce_vs_embree);
  o.shadow = q(a.shadow, b.shadow, a.shadow_vs_embree, b.shadow_vs_embree);
  return o;
}

void print_bench_table(const std::vector<BenchRow>& rows, int build_threads, int repeat, bool batch,
                       const std::string& versus) {
  if (rows.empty()) return;
  // Group titles over the throughput columns, then the column names.
  const std::string lead =
      fmt::format("{:<22} {:>9} {:>7} {:>9} {:>5} {:>9} ", "", "", "", "", "", "");
  std::string titles = lead, names = fmt::format("{:<22} {:>9} {:>7} {:>9} {:>5} {:>9} ", "accel",
                                                 "build ms", "MiB", "nodes", "depth", "refs/prim");
  for (const BenchRates& r : rows.front().rates) {
    titles += fmt::format("|{:^{}}", thread_label(r.threads) + ", Mrays/s", kGroupWidth);
    names += fmt::format("|{:>{}} {:>{}} {:>{}} {:>{}} {:>{}} {:>{}} ", "primary", kRateWidth,
                         "incoher.", kRateWidth, "occlus.", kRateWidth, "bounce", kRateWidth,
                         "shadow", kRateWidth, "x embree", kRateWidth);
  }
  fmt::print("{}|\n{}| {:>12}\n", titles, names, "vs embree");
  for (const BenchRow& r : rows) {
    std::string line = fmt::format("{:<22} {:>9.1f} {:>7.1f} {:>9} {:>5} {:>9} ", r.accel,
                                   r.build_ms, double(r.bytes) / (1 << 20), or_dash(r.nodes, "{}"),
                                   or_dash(r.depth, "{}"), or_dash(r.refs_per_prim, "{:.2f}"));
    for (const BenchRates& t : r.rates)
      line += fmt::format("|{:>{}.2f} {:>{}.2f} {:>{}.2f} {:>{}.2f} {:>{}.2f} {:>{}} ", t.primary,
                          kRateWidth, t.incoherent, kRateWidth, t.occlusion, kRateWidth, t.bounce,
                          kRateWidth, t.shadow, kRateWidth,
                          or_dash(t.incoherent_vs_embree, "{:.2f}"), kRateWidth);
    const std::string cmp =
        r.mismatches ? fmt::format("{} ({} ties)", *r.mismatches, r.ties.value_or(0)) : "-";
    fmt::print("{}| {:>12}\n", line, cmp);
  }
  // The other ratios to Embree, one line per structure and thread count.
  for (const BenchRow& r : rows)
    for (const BenchRates& t : r.rates)
      if (t.primary_vs_embree)
        fmt::print(
            "{:<22} x embree at {}: primary {:.2f}, occlusion {:.2f}, bounce {:.2f}, "
            "shadow {:.2f}\n",
            r.accel, thread_label(t.threads), *t.primary_vs_embree, *t.occlusion_vs_embree,
            *t.bounce_vs_embree, *t.shadow_vs_embree);
  // Every other structure over the --versus one, at each thread count.
  if (const BenchRow* base = versus.empty() ? nullptr : find_row(rows, versus))
    for (const BenchRow& r : rows) {
      if (&r == base || r.accel.rfind("embree", 0) == 0) continue;
      for (size_t i = 0; i < r.rates.size() && i < base->rates.size(); ++i) {
        const BenchOver o = bench_over(r.rates[i], base->rates[i]);
        fmt::print(
            "{:<22} over {} at {}: primary {:.2f}, incoherent {:.2f}, occlusion {:.2f}, bounce "
            "{:.2f}, shadow {:.2f} ({})\n",
            r.accel, versus, thread_label(r.rates[i].threads), o.primary, o.incoherent, o.occlusion,
            o.bounce, o.shadow, o.through_embree ? "their ratios to Embree" : "their rates");
      }
    }
  // The structures' own counts of each set's queries.
  for (const BenchRow& r : rows)
    if (r.counts) {
      const BenchCounts& c = *r.counts;
      std::string figures;
      for (const auto& [key, value] : r.extra) figures += fmt::format("; {} {:g}", key, value);
      fmt::print(
          "{:<22} per ray, nodes visited / primitive tests: primary {:.1f} / {:.1f}, incoherent "
          "{:.1f} / {:.1f}, occlusion {:.1f} / {:.1f}, bounce {:.1f} / {:.1f}, shadow {:.1f} / "
          "{:.1f}{}\n",
          r.accel, c.primary.nodes, c.primary.prims, c.incoherent.nodes, c.incoherent.prims,
          c.occlusion.nodes, c.occlusion.prims, c.bounce.nodes, c.bounce.prims, c.shadow.nodes,
          c.shadow.prims, figures);
      fmt::print(
          "{:<22} incoherent rays: {:.1f} % hit something; per ray that hits, closest {:.1f} / "
          "{:.1f}, any {:.1f} / {:.1f}; per ray that misses {:.1f} / {:.1f}\n",
          r.accel, 100.0 * double(c.incoherent_hits) / double(std::max<size_t>(1, c.incoherent_rays)),
          c.incoherent_hit.nodes, c.incoherent_hit.prims, c.occlusion_hit.nodes,
          c.occlusion_hit.prims, c.incoherent_miss.nodes, c.incoherent_miss.prims);
    }
  fmt::print(
      "(build ms at {} and Mrays/s: medians of {} run(s); refs/prim: leaf references per "
      "triangle.\n"
      " primary = closest hits of the camera's rays, incoher. = closest hits of random rays,\n"
      " occlus. = any hit of the same rays, bounce = closest hits of one diffuse bounce from each\n"
      " camera hit, shadow = any hit of a shadow ray from each camera hit to a square light above\n"
      " the mesh. x embree: incoherent throughput over Embree's, median\n"
      " of runs that alternate with Embree's every 131,072 rays. 'vs embree': incoherent closest\n"
      " hits differing from Embree's, hit vs miss or t beyond 1e-4 relative; ties: same t,\n"
      " another triangle)\n",
      thread_label(build_threads), repeat);
  for (const BenchRow& r : rows)
    if (r.accel == "embree:robust")
      fmt::print(
          "(Embree in its robust mode, RTC_SCENE_FLAG_ROBUST: conservative box tests and its\n"
          " watertight triangle test, the guarantees of our structures)\n");
  if (batch)
    fmt::print(
        "(batch queries: intersect_batch and occluded_batch on 256 rays at a time, against\n"
        " Embree's rtcIntersect1M and rtcOccluded1M: Embree's coherent mode for the primary\n"
        " rays, our interleaving for the incoherent and occlusion rays)\n");
}

void write_bench_json(const std::string& path, const std::vector<BenchRow>& rows,
                      const std::string& mesh, size_t triangles, int build_threads, bool batch,
                      const std::string& versus) {
  const BenchRow* base = versus.empty() ? nullptr : find_row(rows, versus);
  nlohmann::json out = nlohmann::json::array();
  // Which Embree the ratios are against, when one ran (accel-bench --embree-robust).
  std::string embree_mode;
  for (const BenchRow& r : rows)
    if (r.accel == "embree" || r.accel == "embree:robust")
      embree_mode = r.accel == "embree" ? "default" : "robust";
  for (const BenchRow& r : rows) {
    const bool over = base && &r != base && r.accel.rfind("embree", 0) != 0;
    nlohmann::json runs = nlohmann::json::array();
    for (size_t i = 0; i < r.rates.size(); ++i) {
      const BenchRates& t = r.rates[i];
      nlohmann::json run = {{"threads", t.threads},
                            {"primary_mrays", t.primary},
                            {"incoherent_mrays", t.incoherent},
                            {"occlusion_mrays", t.occlusion},
                            {"bounce_mrays", t.bounce},
                            {"shadow_mrays", t.shadow}};
      if (t.incoherent_vs_embree)
        run["primary_vs_embree"] = *t.primary_vs_embree,
        run["incoherent_vs_embree"] = *t.incoherent_vs_embree,
        run["occlusion_vs_embree"] = *t.occlusion_vs_embree,
        run["bounce_vs_embree"] = *t.bounce_vs_embree,
        run["shadow_vs_embree"] = *t.shadow_vs_embree;
      if (over && i < base->rates.size()) {
        const BenchOver o = bench_over(t, base->rates[i]);
        run["over_versus"] = {{"primary", o.primary},     {"incoherent", o.incoherent},
                              {"occlusion", o.occlusion}, {"bounce", o.bounce},
                              {"shadow", o.shadow},       {"through_embree", o.through_embree}};
      }
      runs.push_back(run);
    }
    nlohmann::json o = {{"accel", r.accel},
                        {"mesh", mesh},
                        {"triangles", triangles},
                        {"build_ms", r.build_ms},
                        {"build_threads", build_threads},
                        {"queries", batch ? "batch" : "single"},
                        {"vectors", r.vectors.empty() ? compiled_vectors() : r.vectors},
                        {"bytes", r.bytes},
                        {"runs", runs}};
    if (!embree_mode.empty()) o["embree_mode"] = embree_mode;
    if (over) o["versus"] = versus;
    if (r.nodes) o["nodes"] = *r.nodes;
    if (r.depth) o["depth"] = *r.depth;
    if (r.refs_per_prim) o["refs_per_prim"] = *r.refs_per_prim;
    if (r.mismatches) o["embree_mismatches"] = *r.mismatches;
    if (r.ties) o["embree_ties"] = *r.ties;
    if (r.counts) {
      const BenchCounts& c = *r.counts;
      o["nodes_per_ray"] = c.incoherent.nodes, o["prims_per_ray"] = c.incoherent.prims;
      nlohmann::json per_ray;
      for (const auto& [key, set] : {std::pair{"primary", c.primary},
                                     {"incoherent", c.incoherent},
                                     {"occlusion", c.occlusion},
                                     {"bounce", c.bounce},
                                     {"shadow", c.shadow}})
        per_ray[key] = {{"nodes", set.nodes}, {"prims", set.prims}};
      for (const auto& [key, set] : {std::pair{"incoherent_hit", c.incoherent_hit},
                                     {"incoherent_miss", c.incoherent_miss},
                                     {"occlusion_hit", c.occlusion_hit},
                                     {"occlusion_miss", c.occlusion_miss}})
        per_ray[key] = {{"nodes", set.nodes}, {"prims", set.prims}};
      o["per_ray"] = per_ray;
      o["incoherent_hits"] = c.incoherent_hits;
    }
    for (const auto& [key, value] : r.extra) o[key] = value;
    out.push_back(o);
  }
  write_file_atomically(path, out.dump(2) + "\n");
}

}  // namespace penumbra::app
