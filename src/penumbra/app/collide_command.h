#pragma once
/// `penumbra collide`: the intersecting triangle pairs of two meshes, or the triangles of a mesh
/// that a moving sphere or box touches, found with bounding-volume hierarchies and optionally
/// checked against brute force; prints what was found and the times taken.
#include <cstddef>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace penumbra::app {

/// The options of one collide run; numeric lists are kept as text and parsed by run_collide.
struct CollideArgs {
  std::string mesh_a;                      ///< first mesh (.obj, .ply)
  std::string mesh_b;                      ///< second mesh; empty for sweep queries only
  std::optional<std::string> translate_b;  ///< "x,y,z"
  std::optional<std::string> rotate_b;     ///< "deg,ax,ay,az"
  std::optional<std::string> scale_b;      ///< "s"
  std::optional<std::string> sphere;       ///< "cx,cy,cz,r": a sphere against mesh A
  std::optional<std::string> box;          ///< "minx,miny,minz,maxx,maxy,maxz" against mesh A
  std::optional<std::string> to;           ///< sphere: end centre x,y,z; box: displacement
  bool brute = false;                      ///< also run brute force and compare
  size_t max_print = 10;                   ///< pairs (or triangles) listed
  std::string json;                        ///< when set, results are also written here
  int threads = 0;                         ///< worker threads for the builds; 0 = all cores
};

/// Registers the `collide` subcommand on `app`.
void add_collide_command(CLI::App& app);

/// Runs the queries, printing to stdout; throws Error on bad input, and when brute force
/// disagrees with the hierarchies (after printing both).
void run_collide(const CollideArgs& args);

}  // namespace penumbra::app
