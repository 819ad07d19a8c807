#include "penumbra/app/collide_command.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "penumbra/accel/collision/collision.h"
#include "penumbra/accel/collision/collision_brute.h"
#include "penumbra/app/cli_checks.h"
#include "penumbra/app/mesh_check.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"
#include "penumbra/core/transform.h"
#include "penumbra/geometry/primitive_set.h"
#include "penumbra/scene/mesh_reader.h"

namespace penumbra::app {

namespace {

using collision::CollisionMesh;
using collision::DVec3;
using collision::QueryStats;

/// A query (hierarchy or brute force) is repeated until this much time has passed (or kMaxRepeats
/// runs) and its best time reported: single runs of a millisecond are too noisy to compare.
constexpr double kTimingBudgetMs = 200.0;
constexpr int kMaxRepeats = 100;

/// Parses exactly `count` comma-separated finite numbers from the value of `option`.
std::vector<double> parse_numbers(const std::string& option, const std::string& text, size_t count,
                                  const char* form) {
  std::vector<double> out;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || errno == ERANGE || !std::isfinite(v))
      throw Error(fmt::format("{}: '{}' is not a finite number (expected {})", option, item, form));
    out.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (out.size() != count)
    throw Error(fmt::format("{}: expected {} comma-separated numbers {}, got {} in '{}'", option,
                            count, form, out.size(), text));
  return out;
}

/// Refuses coordinates (and radii, displacements) beyond kMaxCoordinate, as the scene loader and
/// the mesh check do: beyond it the float boxes of the hierarchies overflow.
void check_magnitudes(const std::string& option, const std::vector<double>& values) {
  for (double v : values)
    if (std::fabs(v) > kMaxCoordinate)
      throw Error(
          fmt::format("{}: {:g} is beyond +-{:g}, the largest coordinate penumbra handles "
                      "exactly (docs/robustness.md)",
                      option, v, kMaxCoordinate));
}

/// Refuses a pose that moves a vertex of mesh B beyond kMaxCoordinate.
void check_posed(const CollisionMesh& b, const std::string& pose_text) {
  for (size_t t = 0; t < b.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const DVec3 p = b.triangle(uint32_t(t))[k];
      if (std::fabs(p.x) > kMaxCoordinate || std::fabs(p.y) > kMaxCoordinate ||
          std::fabs(p.z) > kMaxCoordinate)
        throw Error(
            fmt::format("collide: the pose of B ({}) moves a vertex of triangle {} to ({:g}, {:g}, "
                        "{:g}), beyond +-{:g}, the largest coordinate penumbra handles "
                        "exactly",
                        pose_text, t, p.x, p.y, p.z, kMaxCoordinate));
    }
}

/// The pose of mesh B: scale, then rotate, then translate (all about the origin).
Transform pose_b(const CollideArgs& args, std::string& text) {
  Transform pose;
  std::vector<std::string> parts;
  if (args.translate_b) {
    const auto t = parse_numbers("--translate-b", *args.translate_b, 3, "x,y,z");
    check_magnitudes("--translate-b", t);
    // In double, so that the offset is exactly the number given.
    Mat4 m = Mat4::identity(), inv = Mat4::identity();
    for (int k = 0; k < 3; ++k) m.m[k][3] = t[k], inv.m[k][3] = -t[k];
    pose = Transform(m, inv);
    parts.push_back(fmt::format("translate {},{},{}", t[0], t[1], t[2]));
  }
  if (args.rotate_b) {
    const auto r = parse_numbers("--rotate-b", *args.rotate_b, 4, "deg,ax,ay,az");
    if (r[1] == 0 && r[2] == 0 && r[3] == 0)
      throw Error(fmt::format("--rotate-b: the axis of '{}' has zero length", *args.rotate_b));
    pose = pose * rotate(float(r[0]), Vec3(float(r[1]), float(r[2]), float(r[3])));
    parts.insert(parts.begin(),
                 fmt::format("rotate {} deg about {},{},{}", r[0], r[1], r[2], r[3]));
  }
  if (args.scale_b) {
    const double s = parse_numbers("--scale-b", *args.scale_b, 1, "s")[0];
    if (s == 0) throw Error("--scale-b: the scale factor must not be zero");
    Mat4 m = Mat4::identity(), inv = Mat4::identity();
    for (int k = 0; k < 3; ++k) m.m[k][k] = s, inv.m[k][k] = 1.0 / s;
    pose = pose * Transform(m, inv);
    parts.insert(parts.begin(), fmt::format("scale {}", s));
  }
  text = parts.empty() ? "identity" : fmt::format("{}", fmt::join(parts, ", then "));
  return pose;
}

/// Runs `query` repeatedly within the timing budget; returns the best time in ms and keeps the
/// first result.
template <class Result, class Query>
double best_time(Result& result, const Query& query) {
  double best = 1e300, total = 0;
  for (int i = 0; i < kMaxRepeats && (i == 0 || total < kTimingBudgetMs); ++i) {
    const Timer t;
    Result r = query();
    const double ms = t.elapsed_ms();
    if (i == 0) result = std::move(r);
    best = std::min(best, ms), total += ms;
  }
  return best;
}

void describe_mesh(const char* label, const std::string& path, const CollisionMesh& m,
                   const std::string& pose, nlohmann::json& json) {
  const auto& st = m.stats();
  fmt::print("{} {}: {} triangles ({} degenerate or non-finite), pose {}\n", label, path,
             m.triangle_count(), m.triangle_count() - m.valid_count(), pose);
  fmt::print("  hierarchy: built in {:.2f} ms, posed in {:.2f} ms; {} nodes, {} leaves, depth {}\n",
             st.build_ms, st.pose_ms, st.nodes, st.leaves, st.max_depth);
  json = {{"path", path},      {"triangles", m.triangle_count()}, {"valid", m.valid_count()},
          {"pose", pose},      {"build_ms", st.build_ms},         {"pose_ms", st.pose_ms},
          {"nodes", st.nodes}, {"max_depth", st.max_depth}};
}

/// Prints the brute-force comparison; returns whether the answers agree.
template <class T>
bool compare_brute(const std::vector<T>& fast, const std::vector<T>& brute, double ms,
                   double fast_ms, size_t tested, const char* what, nlohmann::json& json) {
  const bool agree = fast == brute;
  fmt::print(
      "brute force: {} {} in {:.2f} ms (best run; {} tested), {:.0f}x the hierarchy query: {}\n",
      brute.size(), what, ms, tested, ms / std::max(fast_ms, 1e-6),
      agree ? "same answer" : "DIFFERENT ANSWER");
  json["brute"] = {{"count", brute.size()}, {"ms", ms}, {"tested", tested}, {"agree", agree}};
  return agree;
}

void print_query(const char* what, size_t count, double ms, const QueryStats& st) {
  fmt::print("{}: {} found in {:.3f} ms (best run; {} node tests, {} exact tests)\n", what, count,
             ms, st.node_tests, st.exact_tests);
}

void write_json(const std::string& path, const nlohmann::json& out) {
  std::ofstream f(path);
  f << out.dump(2) << "\n";
  if (!f) throw Error(fmt::format("{}: cannot write", path));
}

}  // namespace

void add_collide_command(CLI::App& app) {
  auto args = std::make_shared<CollideArgs>();
  CLI::App* cmd = app.add_subcommand(
      "collide",
      "Find the intersecting triangle pairs of two meshes, or the triangles a moving sphere or "
      "box touches (see docs/collision.md)");
  cmd->add_option("A", args->mesh_a, "Mesh (.obj, .ply)")->required();
  cmd->add_option("B", args->mesh_b, "Second mesh: report the intersecting pairs of A and B");
  cmd->add_option("--translate-b", args->translate_b, "Move B by x,y,z (applied last)");
  cmd->add_option("--rotate-b", args->rotate_b, "Rotate B by deg about the axis ax,ay,az");
  cmd->add_option("--scale-b", args->scale_b, "Scale B by s about the origin (applied first)");
  cmd->add_option("--sphere", args->sphere, "Sphere cx,cy,cz,r moving against A (see --to)");
  cmd->add_option("--box", args->box,
                  "Box minx,miny,minz,maxx,maxy,maxz moving against A (see --to)");
  cmd->add_option("--to", args->to,
                  "Motion: the sphere's final centre x,y,z, or the box's displacement dx,dy,dz "
                  "(default: no motion)");
  cmd->add_flag("--brute", args->brute, "Also run brute force, time it and compare the answers");
  cmd->add_option("--max-print", args->max_print, "Pairs or triangles to list (default 10)")
      ->transform(integer_in(0, INT64_MAX));
  cmd->add_option("--json", args->json, "Also write the results (all pairs) to this JSON file");
  cmd->add_option("--threads", args->threads, "Worker threads for the builds (default: all)")
      ->transform(integer_in(1, 4096));
  cmd->callback([args] { run_collide(*args); });
}

void run_collide(const CollideArgs& args) {
  // Check every option before reading meshes.
  if (args.sphere && args.box) throw Error("collide: give --sphere or --box, not both");
  if (args.to && !args.sphere && !args.box) throw Error("collide: --to needs --sphere or --box");
  if (args.mesh_b.empty() && !args.sphere && !args.box)
    throw Error("collide: give a second mesh B, or a --sphere or --box to sweep against A");
  if (args.mesh_b.empty() && (args.translate_b || args.rotate_b || args.scale_b))
    throw Error("collide: --translate-b, --rotate-b and --scale-b need a second mesh B");
  std::string pose_text;
  const Transform pose = pose_b(args, pose_text);
  std::optional<collision::MovingSphere> sphere;
  std::optional<collision::MovingBox> box;
  if (args.sphere) {
    const auto s = parse_numbers("--sphere", *args.sphere, 4, "cx,cy,cz,r");
    check_magnitudes("--sphere", s);
    if (s[3] < 0) throw Error(fmt::format("--sphere: the radius {} is negative", s[3]));
    const DVec3 c(s[0], s[1], s[2]);
    DVec3 to = c;
    if (args.to) {
      const auto t = parse_numbers("--to", *args.to, 3, "x,y,z");
      check_magnitudes("--to", t);
      to = {t[0], t[1], t[2]};
    }
    sphere = collision::MovingSphere{c, to, s[3]};
  }
  if (args.box) {
    const auto b = parse_numbers("--box", *args.box, 6, "minx,miny,minz,maxx,maxy,maxz");
    check_magnitudes("--box", b);
    const DVec3 lo(b[0], b[1], b[2]), hi(b[3], b[4], b[5]);
    if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z)
      throw Error(fmt::format("--box: a minimum exceeds its maximum in '{}'", *args.box));
    DVec3 d;
    if (args.to) {
      const auto t = parse_numbers("--to", *args.to, 3, "dx,dy,dz");
      check_magnitudes("--to", t);
      d = {t[0], t[1], t[2]};
    }
    box = collision::MovingBox{{lo, hi}, d};
  }

  const ThreadLimit limit(args.threads);
  nlohmann::json out;
  const Timer load;
  std::vector<std::string> warnings;
  const TriangleMesh mesh_a = read_mesh(args.mesh_a, &warnings);
  const TriangleMesh mesh_b =
      args.mesh_b.empty() ? TriangleMesh() : read_mesh(args.mesh_b, &warnings);
  print_warnings(warnings);
  check_mesh_input(mesh_a, args.mesh_a);
  if (!args.mesh_b.empty()) check_mesh_input(mesh_b, args.mesh_b);
  fmt::print("loaded in {:.0f} ms; builds on {} thread(s), queries on one\n", load.elapsed_ms(),
             thread_count());
  const CollisionMesh a(mesh_a);
  describe_mesh("A", args.mesh_a, a, "identity", out["a"]);
  bool agree = true;

  if (!args.mesh_b.empty()) {
    const CollisionMesh b(mesh_b, pose);
    check_posed(b, pose_text);
    describe_mesh("B", args.mesh_b, b, pose_text, out["b"]);
    QueryStats st;
    std::vector<collision::TrianglePair> pairs;
    const double ms = best_time(pairs, [&] { return collision::intersecting_pairs(a, b, &st); });
    print_query("intersecting triangle pairs (A, B)", pairs.size(), ms, st);
    for (size_t i = 0; i < std::min(args.max_print, pairs.size()); ++i)
      fmt::print("  {} {}\n", pairs[i].a, pairs[i].b);
    if (pairs.size() > args.max_print) fmt::print("  ... {} more\n", pairs.size() - args.max_print);
    nlohmann::json list = nlohmann::json::array();
    for (const auto& p : pairs) list.push_back({p.a, p.b});
    out["pairs"] = {{"count", pairs.size()},
                    {"query_ms", ms},
                    {"node_tests", st.node_tests},
                    {"exact_tests", st.exact_tests},
                    {"list", list}};
    if (args.brute) {
      std::vector<collision::TrianglePair> brute;
      const double brute_ms =
          best_time(brute, [&] { return collision::intersecting_pairs_brute(a, b); });
      agree &= compare_brute(pairs, brute, brute_ms, ms, a.triangle_count() * b.triangle_count(),
                             "pairs", out["pairs"]);
      fmt::print("  with both hierarchy builds counted: {:.0f}x\n",
                 brute_ms / std::max(ms + a.stats().build_ms + b.stats().build_ms, 1e-6));
    }
  }

  if (sphere || box) {
    QueryStats st;
    std::vector<uint32_t> hits;
    double ms = 0;
    std::string what;
    if (sphere) {
      const auto& s = *sphere;
      what = fmt::format("triangles touched by the sphere r={} moving ({},{},{}) -> ({},{},{})",
                         s.radius, s.from.x, s.from.y, s.from.z, s.to.x, s.to.y, s.to.z);
      ms = best_time(hits, [&] { return collision::touched_triangles(a, s, &st); });
    } else {
      const auto& b = *box;
      what = fmt::format("triangles touched by the box ({},{},{})-({},{},{}) moving by ({},{},{})",
                         b.box.lo.x, b.box.lo.y, b.box.lo.z, b.box.hi.x, b.box.hi.y, b.box.hi.z,
                         b.displacement.x, b.displacement.y, b.displacement.z);
      ms = best_time(hits, [&] { return collision::touched_triangles(a, b, &st); });
    }
    print_query(what.c_str(), hits.size(), ms, st);
    const size_t shown = std::min(args.max_print, hits.size());
    if (shown > 0)
      fmt::print("  {}{}\n", fmt::join(hits.begin(), hits.begin() + shown, " "),
                 hits.size() > shown ? fmt::format(" ... {} more", hits.size() - shown) : "");
    out["sweep"] = {{"query", what},
                    {"count", hits.size()},
                    {"query_ms", ms},
                    {"node_tests", st.node_tests},
                    {"exact_tests", st.exact_tests},
                    {"triangles", hits}};
    if (args.brute) {
      std::vector<uint32_t> brute;
      const double brute_ms = best_time(brute, [&] {
        return sphere ? collision::touched_triangles_brute(a, *sphere)
                      : collision::touched_triangles_brute(a, *box);
      });
      agree &=
          compare_brute(hits, brute, brute_ms, ms, a.triangle_count(), "triangles", out["sweep"]);
    }
  }

  if (!args.json.empty()) write_json(args.json, out);
  if (!agree)
    throw Error(
        "collide: the hierarchy and brute force disagree (a bug: please report it with "
        "the command line)");
}

}  // namespace penumbra::app
