#include "penumbra/accel/registry.h"

#include <functional>

#include <fmt/format.h>

#include "penumbra/accel/brute_force.h"
#include "penumbra/accel/bsp_tree.h"
#include "penumbra/accel/bvh.h"
#include "penumbra/accel/kdtree.h"
#include "penumbra/accel/octree.h"
#include "penumbra/accel/uniform_grid.h"
#include "penumbra/accel/wide_bvh.h"
#include "penumbra/core/error.h"
#include "penumbra/core/registry.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Accelerator>(const ParamList&)>;

template <class T>
std::unique_ptr<Accelerator> create(const ParamList& p) {
  return std::make_unique<T>(p);
}

/// The width of `bvh` when none is given, by what the target's vectors are (docs/accel.md,
/// "2026-12-06, fifteenth session", builds for four x86-64 levels measured on one Xeon):
/// - 16 with AVX: the node test is two 256-bit registers per row, with or without AVX2 or
///   AVX-512, and beat 8 on every mesh and ray set but the small meshes' camera rays (incoherent
///   rays 0.87-1.10 -> 0.95-1.22 x Embree in AVX and AVX2 builds; with AVX-512 since the
///   twelfth session);
/// - 4 without (SSE, or no x86 vectors): one 128-bit register per row; 8 and 16 were slower on
///   every mesh and ray set of an SSE2 build (incoherent rays 0.72-0.93 x Embree with 4, 0.62-0.83
///   with 8; camera rays 0.81-1.26 against 0.55-0.72).
int default_bvh_width() {
#if defined(__AVX__)
  return 16;
#else
  return 4;
#endif
}

/// `bvh`: the BVH of the chosen width (default_bvh_width()). nodes=compressed and order=octant
/// exist for width 8 only, which they imply when no width is given.
std::unique_ptr<Accelerator> create_bvh(const ParamList& p) {
  const std::string nodes = p.get_string("nodes", "full");
  if (nodes != "full" && nodes != "compressed")
    throw Error(
        fmt::format("{}: parameter 'nodes' must be full or compressed, got '{}'", p.name(), nodes));
  int width = int(p.get_int("width", 0, 2, 16));  // 0: not given
  if (width == 0)
    width = nodes == "compressed" || p.get_string("order", "distance") == "octant"
                ? 8
                : default_bvh_width();
  if (width != 2 && width != 4 && width != 8 && width != 16)
    throw Error(
        fmt::format("{}: parameter 'width' must be 2, 4, 8 or 16, got {}", p.name(), width));
  if (nodes == "compressed" && width != 8)
    throw Error(fmt::format("{}: nodes=compressed needs width=8, got width={}", p.name(), width));
  switch (width) {
    case 2:
      return std::make_unique<Bvh>(p);
    case 4:
      return std::make_unique<WideBvh<4>>(p);
    case 8:
      if (nodes == "compressed") return std::make_unique<WideBvh<8, CompressedNode>>(p);
      return std::make_unique<WideBvh<8>>(p);
    default:
      return std::make_unique<WideBvh<16>>(p);
  }
}

/// Every structure, written out explicitly: a new one is one line here.
const Registry<Factory>& registry() {
  static const Registry<Factory> all = {
      {"brute", "brute force: every primitive for every ray (the reference)", create<BruteForce>},
      {"bvh",
       "BVH, binned SAH build, width=16 on AVX targets, else 4 (SIMD wide nodes; 8, or 2 "
       "for binary), leaf=16 for width 16, else 8, bins=32 for width 16, else 16, "
       "trav=2, build=binned|median|sweep, exact=auto (binned: nodes of up to N references, "
       "N <= 256, split by the exact SAH; auto: 64 for width 16 over sets of up to 2^16 "
       "primitives, else 0), collapse=sah|greedy, nodes=full|compressed (8-wide: "
       "float boxes, 256 bytes, or byte planes, 128 bytes), presplit=0 (up to F x the triangles "
       "as extra references for large triangles, F in [0, 4]), spatial=1 (SBVH spatial splits: "
       "up to F x the triangles as extra references, F in [0, 4], binned builds of static "
       "triangles; 0 turns them off), alpha=0.001 (tried where the object split's children "
       "overlap by more than this share of the root's area), optimize=auto (treelet "
       "restructuring passes of the binary tree, 0-16; auto: one for sets of up to 2^18 "
       "primitives, none above), order=distance|octant (8-wide: closest-hit rays visit "
       "children nearest first, or in their octant's order), anyhit=auto|span|lanes (the inner "
       "child an any-hit ray visits first when no leaf is hit: the longest span through its "
       "box, or the lowest lane; auto: span on Intel CPUs, lanes on others)",
       create_bvh},
      // Variants listed (name:params) so that `all` and the differential tests cover them.
      {"bvh:median", "bvh built by object-median splits (build=median)", create_bvh},
      {"bvh:sweep", "bvh built by full-sweep SAH over all object partitions (build=sweep)",
       create_bvh},
      {"bvh:nodes=compressed", "bvh with 128-byte nodes, child boxes quantised to bytes",
       create_bvh},
      // Both SIMD widths whatever the target's default (16 is `bvh` itself with AVX; bvh4 below
      // is the default without).
      {"bvh:width=8", "bvh with 8-wide nodes (256 bytes), leaves of up to 8", create_bvh},
      {"bvh:width=16", "bvh with 16-wide nodes (512 bytes), leaves of up to 16", create_bvh},
      {"bvh:collapse=greedy",
       "bvh collapsed from the binary tree greedily (largest-area child opened first)", create_bvh},
      {"bvh:order=octant",
       "bvh whose closest-hit rays visit children in their octant's order, not by distance",
       create_bvh},
      {"bvh:spatial=0",
       "bvh without spatial splits (object splits only, one reference per triangle)", create_bvh},
      {"bvh:optimize=0",
       "bvh without treelet restructuring (the binary tree as the binned SAH built it)",
       create_bvh},
      {"bvh:presplit=0.5",
       "bvh over pre-split large triangles: up to 50 % more references, split at grid planes",
       create_bvh},
      {"bvh2", "binary BVH (bvh:width=2), 32-byte nodes, nearer child first", create<Bvh>},
      {"bsp", "3D BSP by auto-partition (order=random|first|fewest-cuts, seed=1, depth=256)",
       create<BspTree>},
      {"grid", "uniform grid, exact cell overlap, 3D-DDA, mailbox (lambda=1)", create<UniformGrid>},
      {"octree", "octree, exact octant overlap, front-to-back walk, mailbox (leaf=16, depth=16)",
       create<Octree>},
      {"bvh4", "4-wide BVH (bvh:width=4) collapsed from the binary one, SIMD box tests",
       create<WideBvh<4>>},
      {"kdtree",
       "kd-tree, O(N log N) SAH build with perfect splits (sah|median|gap, ct=1, ci=0.4 per block)",
       create<KdTree>},
  };
  return all;
}

}  // namespace

const std::vector<AccelInfo>& accelerator_list() {
  static const std::vector<AccelInfo> list = [] {
    std::vector<AccelInfo> l;
    for (const auto& e : registry().entries()) l.push_back({e.name, e.description});
    return l;
  }();
  return list;
}

std::unique_ptr<Accelerator> make_accelerator(std::string_view spec) {
  const ParamList params = ParamList::parse(spec);
  if (const Factory* make = registry().find(params.name())) return (*make)(params);
  const std::string names = registry().valid_names(  // not the listed variants
      [](const std::string& name) { return name.find(':') == std::string::npos; });
  throw Error(fmt::format("unknown acceleration structure '{}' (valid: {})", params.name(), names));
}

}  // namespace penumbra
