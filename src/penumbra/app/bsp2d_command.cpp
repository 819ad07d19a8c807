#include "penumbra/app/bsp2d_command.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "penumbra/accel2d/random_segments.h"
#include "penumbra/accel2d/registry2d.h"
#include "penumbra/app/bsp2d_experiment.h"
#include "penumbra/app/cli_checks.h"
#include "penumbra/app/svg2d.h"
#include "penumbra/core/error.h"
#include "penumbra/core/params.h"

namespace penumbra::app {

namespace {

/// The ray "x,y,dx,dy" given to --ray.
Ray2 parse_ray(const std::string& text) {
  std::vector<double> v;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || errno == ERANGE || !std::isfinite(x))
      throw Error(fmt::format("--ray: '{}' is not a finite number (expected X,Y,DX,DY)", item));
    v.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (v.size() != 4)
    throw Error(fmt::format("--ray: expected 4 numbers X,Y,DX,DY, got {} in '{}'", v.size(), text));
  if (v[2] == 0 && v[3] == 0) throw Error("--ray: the direction DX,DY is zero");
  return {{v[0], v[1]}, {v[2], v[3]}};
}

/// A ray across the scene when none is given: from left of its box, through the middle.
Ray2 default_ray(const lab2d::Scene2D& scene) {
  Box2d b = scene.bounds();
  if (b.empty()) b = {{0, 0}, {1, 1}};
  const Vec2d e = b.extent();
  return {{b.lo.x - 0.05 * e.x, b.lo.y + 0.4871 * e.y},
          {1, 0.0731 * (e.y > 0 ? e.y / std::max(e.x, 1e-300) : 0)}};
}

/// The full structure spec: --structure with --order and --seed folded in for the BSP.
std::string structure_spec(const Bsp2DArgs& args) {
  const ParamList p = ParamList::parse(args.structure);
  const bool has_params = args.structure.find(':') != std::string::npos;
  if (p.name() != "bsp") {
    if (args.order) throw Error("--order applies to --structure bsp only");
    return args.structure;
  }
  if (has_params && args.order)
    throw Error("--order: give the order either with --order or as bsp:order=..., not both");
  if (has_params) return args.structure;
  return fmt::format("bsp:order={},seed={}", args.order.value_or("random"), args.seed);
}

}  // namespace

void add_bsp2d_command(CLI::App& app) {
  auto args = std::make_shared<Bsp2DArgs>();
  CLI::App* cmd = app.add_subcommand(
      "bsp2d",
      "The 2D laboratory: BSP trees of segments, quadtrees, kd-trees and grids, ray shooting with "
      "its traversal path, SVG pictures, and the fragment experiment (see docs/lab2d.md)");
  cmd->add_option("INPUT", args->input, "Segment file (text format of docs/lab2d.md)");
  cmd->add_option("--random", args->random, "Generate N random disjoint segments instead")
      ->transform(integer_in(1, 10'000'000));
  std::string names;
  for (const auto& info : lab2d::accel2d_list())
    names += fmt::format("\n  {}: {}", info.name, info.description);
  cmd->add_option("--structure", args->structure, "NAME[:k=v,...] (default bsp):" + names);
  cmd->add_option("--order", args->order, "BSP order: random (default), first, fewest-cuts");
  cmd->add_option("--seed", args->seed, "Seed of the random order and of --random (default 1)")
      ->transform(unsigned_in(0, UINT64_MAX));
  cmd->add_option("--ray", args->ray, "The ray X,Y,DX,DY (default: the file's, or one across)");
  cmd->add_option("--svg", args->svg, "Draw the segments, the partition and the ray here");
  cmd->add_option("--experiment", args->experiment,
                  "'fragments': fragments and build time of 2DRANDOMBSP for n = 100 .. --max-n");
  cmd->add_option("--max-n", args->max_n, "Experiment: the largest n (default 100000)")
      ->transform(integer_in(100, 10'000'000));
  cmd->add_option("--seeds", args->seeds, "Experiment: seeds per n (default 3)")
      ->transform(integer_in(1, 1000));
  cmd->callback([args] { run_bsp2d(*args); });
}

void run_bsp2d(const Bsp2DArgs& args) {
  if (!args.experiment.empty()) {
    if (args.experiment != "fragments")
      throw Error(
          fmt::format("--experiment: unknown experiment '{}' (valid: fragments)", args.experiment));
    if (!args.input.empty() || args.random)
      throw Error("--experiment generates its own inputs: give no INPUT or --random");
    run_fragment_experiment(args.max_n, args.seeds, args.svg);
    return;
  }
  if (args.input.empty() == !args.random)
    throw Error("bsp2d: give an INPUT file or --random N (one of them)");

  // The input, and the checks its structure needs.
  const std::string spec = structure_spec(args);
  auto accel = lab2d::make_accel2d(spec);
  const std::string name = ParamList::parse(spec).name();
  const lab2d::Scene2D scene = args.random ? lab2d::random_segments(*args.random, args.seed)
                                           : lab2d::load_scene2d(args.input);
  // Generated segments are disjoint by construction; a file is checked where the theory needs it.
  for (const auto& info : lab2d::accel2d_list())
    if (info.name == name && info.disjoint && !args.random)
      lab2d::check_disjoint(scene, info.segments_only);
  size_t segments = 0;
  for (const auto& s : scene.shapes) segments += s.is_segment();
  fmt::print("input: {}: {} segments, {} polygons\n", scene.source, segments,
             scene.shapes.size() - segments);

  accel->build(scene);
  const lab2d::Stats2D st = accel->stats();
  const bool bsp = name == "bsp";
  fmt::print("structure: {}\n", accel->name());
  fmt::print("size: {} nodes ({} internal, {} leaves), depth {}, {} {}, build {:.3f} ms\n",
             st.nodes, st.nodes - st.leaves, st.leaves, st.depth, st.fragments,
             bsp ? "fragments" : "references", st.build_ms);
  if (!st.extra.empty()) {
    std::string extra;
    for (const auto& [key, value] : st.extra)
      extra += fmt::format("{}{} {:g}", extra.empty() ? "" : ", ", key, value);
    fmt::print("       {}\n", extra);
  }

  // One ray, its hit and its path.
  Ray2 ray = args.ray ? parse_ray(*args.ray) : (scene.ray ? *scene.ray : default_ray(scene));
  lab2d::TraceLog trace;
  const lab2d::Hit2 hit = accel->shoot(ray, &trace);
  fmt::print("ray: origin ({:g}, {:g}), direction ({:g}, {:g}){}\n", ray.o.x, ray.o.y, ray.d.x,
             ray.d.y, args.ray ? "" : (scene.ray ? " (from the file)" : " (default)"));
  if (hit.hit()) {
    const Vec2d p = ray.o + ray.d * hit.t;
    fmt::print("hit: {}{} at t = {:g}, point ({:g}, {:g})\n",
               scene.shapes[hit.id].is_segment() && name != "objects" ? 's' : 'O', hit.id + 1,
               hit.t, p.x, p.y);
  } else {
    fmt::print("hit: none\n");
  }
  fmt::print("path: {}\n", trace.str());

  if (!args.svg.empty()) {
    Box2d frame = scene.bounds();
    frame.extend(ray.o);
    const Vec2d e = frame.extent();
    const double m = 0.08 * std::max({e.x, e.y, 1e-9});
    frame.lo = frame.lo - Vec2d{m, m};
    frame.hi = frame.hi + Vec2d{m, m};
    const lab2d::Drawing2D drawing = accel->draw(frame);
    Svg2DContent content;
    content.scene = &scene;
    content.drawing = &drawing;
    content.ray = ray;
    content.hit = hit;
    content.title = fmt::format("{} over {} — path: {}", accel->name(), scene.source,
                                trace.tokens().size() <= 24 ? trace.str() : "(see the output)");
    write_text_atomically(args.svg, svg_of_structure(content));
    fmt::print("svg: {}\n", args.svg);
  }
}

}  // namespace penumbra::app
