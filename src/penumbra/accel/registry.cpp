#include "penumbra/accel/registry.h"

#include <cstdlib>
#include <functional>

#include <fmt/format.h>

#include "penumbra/accel/brute_force.h"
#include "penumbra/accel/bsp_tree.h"
#include "penumbra/accel/bvh.h"
#include "penumbra/accel/kdtree.h"
#include "penumbra/accel/octree.h"
#include "penumbra/accel/uniform_grid.h"
#include "penumbra/accel/wide_bvh.h"
#include "penumbra/core/cpu_check.h"
#include "penumbra/core/error.h"
#include "penumbra/core/registry.h"
#include "penumbra/core/target.h"

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

/// The factory of the structure `params` names; throws Error listing the valid names.
const Factory& find_factory(const ParamList& params) {
  if (const Factory* make = registry().find(params.name())) return *make;
  const std::string names = registry().valid_names(  // not the listed variants
      [](const std::string& name) { return name.find(':') == std::string::npos; });
  throw Error(fmt::format("unknown acceleration structure '{}' (valid: {})", params.name(), names));
}

/// The structure named by `params` as this copy of the code builds it. `isa` was the
/// dispatcher's (make_accelerator): read here so that the name keeps it.
std::unique_ptr<Accelerator> make_here(const ParamList& params) {
  (void)params.get_string("isa", "auto");
  return find_factory(params)(params);
}

}  // namespace

#if defined(PENUMBRA_ISA_LEVEL)
// This file compiled again for one instruction-set level (CMakeLists.txt): the level's two
// entry points, the only symbols its object leaves global.
#define PENUMBRA_ISA_CAT2(a, b, c) a##b##c
#define PENUMBRA_ISA_CAT(a, b, c) PENUMBRA_ISA_CAT2(a, b, c)
#define PENUMBRA_ISA_ENTRY(what) PENUMBRA_ISA_CAT(penumbra_isa_, PENUMBRA_ISA_LEVEL, _##what)

extern "C" Accelerator* PENUMBRA_ISA_ENTRY(make)(const char* spec, size_t size) {
  return make_here(ParamList::parse(std::string_view(spec, size))).release();
}

extern "C" int PENUMBRA_ISA_ENTRY(missing)(const char* lacks, const char** out) {
  return missing_cpu_features(lacks, out);
}

#else
// The levels compiled into the program (CMakeLists.txt defines PENUMBRA_HAVE_ISA_*).
#define PENUMBRA_ISA_DECLARE(level)                                         \
  extern "C" Accelerator* penumbra_isa_##level##_make(const char*, size_t); \
  extern "C" int penumbra_isa_##level##_missing(const char*, const char**);
#if defined(PENUMBRA_HAVE_ISA_SSE2)
PENUMBRA_ISA_DECLARE(sse2)
#endif
#if defined(PENUMBRA_HAVE_ISA_AVX2)
PENUMBRA_ISA_DECLARE(avx2)
#endif
#if defined(PENUMBRA_HAVE_ISA_AVX512)
PENUMBRA_ISA_DECLARE(avx512)
#endif

namespace {

/// A level the structures were compiled for besides the build's own target.
struct IsaLevel {
  const char* name;  ///< what isa= takes
  int rank;          ///< wider vectors rank higher (isa_rank)
  Accelerator* (*make)(const char*, size_t);
  int (*missing)(const char*, const char**);
};

/// The levels compiled in, in increasing width.
const std::vector<IsaLevel>& compiled_levels() {
  static const std::vector<IsaLevel> levels = [] {
    std::vector<IsaLevel> l;
#if defined(PENUMBRA_HAVE_ISA_SSE2)
    l.push_back({"sse2", 10, penumbra_isa_sse2_make, penumbra_isa_sse2_missing});
#endif
#if defined(PENUMBRA_HAVE_ISA_AVX2)
    l.push_back({"avx2", 30, penumbra_isa_avx2_make, penumbra_isa_avx2_missing});
#endif
#if defined(PENUMBRA_HAVE_ISA_AVX512)
    l.push_back({"avx512", 40, penumbra_isa_avx512_make, penumbra_isa_avx512_missing});
#endif
    return l;
  }();
  return levels;
}

/// The rank of compiled_vectors() names, as IsaLevel::rank.
int isa_rank(std::string_view vectors) {
  if (vectors == "AVX-512") return 40;
  if (vectors == "AVX2") return 30;
  if (vectors == "AVX") return 20;
  if (vectors == "SSE4.2") return 11;
  if (vectors == "SSE2") return 10;
  return 0;
}

/// The extensions level `l` needs that this CPU lacks (or `lacks` names), comma-separated.
std::string isa_missing(const IsaLevel& l, const char* lacks) {
  const char* out[kMaxCpuFeatures];
  const int n = l.missing(lacks, out);
  std::string list;
  for (int i = 0; i < n; ++i) list += (i ? ", " : "") + std::string(out[i]);
  return list;
}

const IsaLevel* find_isa(std::string_view name) {
  for (const IsaLevel& l : compiled_levels())
    if (name == l.name) return &l;
  return nullptr;
}

}  // namespace

std::vector<std::string> isa_levels() {
  std::vector<std::string> names;
  for (const IsaLevel& l : compiled_levels()) names.emplace_back(l.name);
  return names;
}

std::string isa_auto(const char* lacks) {
  const IsaLevel* best = nullptr;
  int rank = isa_rank(compiled_vectors());  // the build's own code wins ties
  for (const IsaLevel& l : compiled_levels())
    if (l.rank > rank && isa_missing(l, lacks).empty()) best = &l, rank = l.rank;
  return best ? best->name : "native";
}

const std::vector<AccelInfo>& accelerator_list() {
  static const std::vector<AccelInfo> list = [] {
    std::vector<AccelInfo> l;
    for (const auto& e : registry().entries()) l.push_back({e.name, e.description});
    // The copies for the x86-64 baseline, listed so that `all` and the differential, batch and
    // rendering tests cover them on every machine (isa=, registry.h).
    if (find_isa("sse2")) {
      l.push_back({"bvh:isa=sse2",
                   "bvh compiled for SSE2 (the x86-64 baseline), chosen when the program runs: "
                   "4-wide"});
      l.push_back({"kdtree:sah,isa=sse2", "kdtree compiled for SSE2 (the x86-64 baseline)"});
    }
    return l;
  }();
  return list;
}

std::unique_ptr<Accelerator> make_accelerator(std::string_view spec) {
  const ParamList params = ParamList::parse(spec);
  // An unknown name is reported as such, whatever its isa.
  (void)find_factory(params);
  // PENUMBRA_CPU_LACKS: the start-up check's test hook (core/cpu_check.h).
  const char* lacks = std::getenv("PENUMBRA_CPU_LACKS");
  std::string isa = params.get_string("isa", "auto");
  if (isa == "auto") isa = isa_auto(lacks);
  if (isa == "native") return make_here(params);
  const IsaLevel* level = find_isa(isa);
  if (!level) {
    std::string valid = "auto, native";
    for (const std::string& name : isa_levels()) valid += ", " + name;
    throw Error(
        fmt::format("{}: parameter 'isa' must be one of {}, got '{}'", params.name(), valid, isa));
  }
  if (const std::string missing = isa_missing(*level, lacks); !missing.empty())
    throw Error(
        fmt::format("{}: isa={} needs {}, which this CPU lacks", params.name(), isa, missing));
  return std::unique_ptr<Accelerator>(level->make(spec.data(), spec.size()));
}
#endif

}  // namespace penumbra
