#include "penumbra/app/convert_command.h"

#include <cstdio>
#include <filesystem>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/image/image_io.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/scene/scene_writer.h"

namespace penumbra::app {

namespace fs = std::filesystem;

void add_convert_command(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* cmd = app.add_subcommand(
      "convert",
      "Write a scene (JSON, pbrt-v4, ...) as a JSON scene with its meshes as PLY files beside it");
  cmd->add_option("scene", args->input, "Scene file to read (.json, .pbrt)")->required();
  cmd->add_option("-o,--output", args->output, "JSON scene to write")->required();
  cmd->add_option("--mesh-dir", args->mesh_dir,
                  "Folder for the meshes, relative to the output's folder (default: "
                  "<output stem>-meshes)");
  cmd->add_flag("-q,--quiet", args->quiet, "Print no summary");
  cmd->callback([args] { run_convert(*args); });
}

void run_convert(const ConvertArgs& args) {
  const fs::path out(args.output);
  if (out.extension() != ".json")
    throw Error(
        fmt::format("-o {}: the converted scene is a JSON file; name it *.json", args.output));
  const fs::path mesh_dir =
      args.mesh_dir.empty() ? fs::path(out.stem().string() + "-meshes") : fs::path(args.mesh_dir);
  if (mesh_dir.is_absolute() || mesh_dir.lexically_normal().string().starts_with(".."))
    throw Error(
        fmt::format("--mesh-dir {}: must be a folder below the output's folder", args.mesh_dir));
  const SceneDesc scene = load_scene(args.input);
  for (const std::string& w : scene.warnings) fmt::print(stderr, "warning: {}\n", w);
  const std::vector<SceneFile> files =
      write_scene_json(scene, out.filename().string(), mesh_dir.generic_string());

  // Every path is checked before anything is written, so a bad one costs no partial output.
  const fs::path base = out.parent_path();
  check_writable(args.output);
  size_t bytes = 0;
  for (size_t i = 1; i < files.size(); ++i) {
    const fs::path p = base / files[i].path;
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    if (ec)
      throw Error(fmt::format("{}: cannot create: {}", p.parent_path().string(), ec.message()));
    check_writable(p.string());
    bytes += files[i].bytes.size();
  }
  // Meshes first and the scene last: a scene file on disk always has its meshes.
  for (size_t i = 1; i < files.size(); ++i)
    write_file_atomically((base / files[i].path).string(), files[i].bytes);
  write_file_atomically(args.output, files[0].bytes);
  if (!args.quiet)
    fmt::print(stderr,
               "wrote {} ({} shapes, {} objects, {} instances) and {} PLY meshes and {} images "
               "({}) in {}\n",
               args.output, scene.shapes.size(), scene.objects.size(), scene.instances.size(),
               files.size() - 1 - scene.images.size(), scene.images.size(),
               format_bytes(double(bytes)), (base / mesh_dir).string());
}

}  // namespace penumbra::app
