#pragma once
/// Construction of a 3D binary space partition by auto-partition: every splitting plane is the
/// supporting plane of one of the node's triangles or parallelograms (de Berg, Cheong, van Kreveld,
/// Overmars 2008, "Computational Geometry: Algorithms and Applications", 3rd ed., ch. 12;
/// Paterson, Yao 1990, "Efficient binary space partitions for hidden-surface removal and solid
/// modeling", Discrete Comput. Geom. 5). The default order is 3DRANDOMBSP: a seeded random
/// permutation, then at every node the plane of the first remaining fragment in that order.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "penumbra/accel/build/bsp_polygon.h"
#include "penumbra/core/params.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// How a node chooses its splitting plane among its fragments.
enum class BspOrder : uint8_t {
  kRandom,      ///< first fragment in a seeded random permutation of the input (3DRANDOMBSP)
  kFirst,       ///< first fragment in input order
  kFewestCuts,  ///< among sampled candidates, the plane cutting the fewest sampled fragments
};

/// Deepest node the builder makes; the traversal stack holds two entries per level.
inline constexpr int kBspMaxDepth = 1024;
/// Traversal stack size that covers every tree this builder makes.
inline constexpr int kBspStackSize = 2 * kBspMaxDepth;
/// Fragments sampled to score one candidate plane in the fewest-cuts order.
inline constexpr int kBspCutSample = 128;
/// Build tolerance relative to the scene scale: a vertex this close to a plane lies in it.
inline constexpr double kBspBuildEps = 1e-6;
/// Traversal tolerance relative to the scene scale plus the ray origin's largest coordinate: the
/// regions a ray visits are widened by it. Ten times the build tolerance, which leaves room for the
/// float rounding of the planes (about 2e-7) and of the triangle test's hit points.
inline constexpr double kBspTraversalEps = 1e-5;

/// Settings of the BSP build.
struct BspBuildParams {
  BspOrder order = BspOrder::kRandom;
  uint64_t seed = 1;    ///< permutation seed (random and fewest-cuts orders)
  int candidates = 32;  ///< fewest-cuts: planes scored per node
  int max_depth = 256;  ///< deeper nodes become leaves holding their remaining fragments
  size_t max_fragments = size_t(1) << 24;  ///< the build stops with an Error beyond this
};

/// Reads order=random|first|fewest-cuts, seed=N, candidates=N (1..1024), depth=N
/// (1..kBspMaxDepth) and max_fragments=N (1..2^31) from `params`, the defaults being those of
/// BspBuildParams; throws Error on bad values. Unused keys are left for the caller.
BspBuildParams read_bsp_build_params(const ParamList& params);

/// Child index of an empty cell (no node is stored for it).
inline constexpr uint32_t kBspEmpty = 0xffffffffu;
/// child[0] of a leaf.
inline constexpr uint32_t kBspLeaf = 0xfffffffeu;

/// One node, 32 bytes: an inner node's plane n.x = d with the primitives lying in it, or a leaf's
/// primitives (non-planar objects, or the fragments left when the depth cap was hit).
struct BspNode {
  Vec3 n;                                      ///< unit normal (inner nodes)
  float d = 0;                                 ///< plane offset (inner nodes)
  uint32_t child[2] = {kBspEmpty, kBspEmpty};  ///< below and above the plane; kBspLeaf for a leaf
  uint32_t first = 0;                          ///< first index into the references
  uint32_t count = 0;  ///< references: coplanar primitives (inner) or leaf primitives

  bool is_leaf() const { return child[0] == kBspLeaf; }
};

/// A built BSP tree with its statistics.
struct BspBuildResult {
  std::vector<BspNode> nodes;  ///< root at 0, depth-first; empty when nothing was built
  std::vector<uint32_t> refs;  ///< primitive ids, each node's range contiguous, no duplicates
  double scale = 0;            ///< largest absolute coordinate of the scene (tolerance unit)
  size_t leaves = 0;           ///< leaf nodes plus empty cells
  size_t empty_cells = 0;      ///< empty leaves (not stored)
  size_t max_depth = 0;        ///< deepest leaf or empty cell
  size_t planar = 0;           ///< triangles and parallelograms that define a plane
  size_t fragments = 0;        ///< final fragments of the planar primitives
  size_t object_refs = 0;      ///< references to non-planar objects in leaves
  size_t capped_leaves = 0;    ///< leaves made by the depth cap
};

/// Receives every final fragment (debugging and tests): its primitive, the node storing it and
/// its polygon.
using BspFragmentSink =
    std::function<void(uint32_t prim, uint32_t node, std::span<const Vec3d> polygon)>;

/// Builds the BSP tree over `prims`, skipping primitives with empty bounds. Triangles and
/// parallelograms are clipped into fragments; spheres, degenerate polygons and moving primitives
/// (which have no fixed plane) are objects pushed to every side they reach (a moving one: at any
/// time of its interval) and stored in leaves. A node left with objects only is split further by
/// the mid-motion plane of one of its moving polygons when that separates them (at least 8
/// objects, best of 8 candidates), so a moving mesh is not one leaf. Deterministic for given
/// parameters. Throws Error when more than params.max_fragments fragments and object references
/// would be made.
BspBuildResult build_bsp(const PrimitiveSet& prims, const BspBuildParams& params,
                         const BspFragmentSink* sink = nullptr);

}  // namespace penumbra
