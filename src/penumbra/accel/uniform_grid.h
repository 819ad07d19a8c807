#pragma once
/// `grid`: uniform spatial subdivision (Fujimoto, Tanaka, Iwata 1986, "ARTS: Accelerated
/// Ray-Tracing System"), traversed cell by cell with the 3D-DDA of Amanatides & Woo 1987, "A
/// Fast Voxel Traversal Algorithm for Ray Tracing".
///
/// The scene box is cut into nx * ny * nz equal cells; about lambda * N near-cubic cells for N
/// primitives (Cleary & Wyvill 1988, "Analysis of an algorithm for fast ray tracing using uniform
/// space subdivision"). A primitive is referenced by every cell it really overlaps (exact
/// triangle/sphere/parallelogram-box tests of build/prim_box_overlap.h), stored compressed:
/// per-cell offsets into one flat array of primitive ids (CSR).
///
/// Parameters (`grid:lambda=4`, `grid:res=64`, `grid:res=64x32x16`):
///   lambda=X    cells per primitive, 0.01..64 (default 1; measured in docs/accel/grid.md)
///   res=N|AxBxC fixed resolution instead (each axis 1..4096; the cell cap below still applies)
///   mailbox=N   per-ray mailbox slots, 0 (off), 8, 16, 32 or 64 (default 16)
///   copy=0|1    triangle-only scenes: copy the vertices into cell order (default 1; skipped
///               above kMaxCopiedRefsPerPrim references per primitive)
/// Caps: at most kMaxAxisCells per axis and max(kMinCellCap, kMaxCellsPerPrim * N) cells in all
/// (never more than kMaxCells), so memory stays linear in N; a resolution over the cap is scaled
/// down uniformly.
#include <array>
#include <span>
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/core/array_allocator.h"
#include "penumbra/core/params.h"

namespace penumbra {

struct PrimRef;

/// Most cells along one axis.
inline constexpr int kMaxAxisCells = 4096;
/// Cells allowed per primitive (the largest lambda); the total-cell cap is linear in N.
inline constexpr double kMaxCellsPerPrim = 64.0;
/// The total-cell cap never falls below this (so small scenes may still use res=128).
inline constexpr size_t kMinCellCap = size_t(1) << 21;
/// Absolute cap on cells (512 MiB of offsets).
inline constexpr size_t kMaxCells = size_t(1) << 27;
/// Reference budget: the primitives' boxes may cover at most this many cells per primitive on
/// average; a finer resolution is lowered (scenes of large overlapping primitives).
inline constexpr double kMaxCandidatesPerPrim = 64.0;
/// Triangle vertices are copied into cell order only up to this many references per primitive.
inline constexpr double kMaxCopiedRefsPerPrim = 8.0;

/// Cells per axis for `n` primitives in a box of extent `d`: n_i = round(d_i * cbrt(lambda n /
/// V)), at least 1; an axis too thin for one cell gets one and the others share the budget.
/// Then the caps above. Deterministic.
std::array<int, 3> grid_resolution(Vec3 d, size_t n, double lambda);
/// `res` scaled down uniformly (each axis at least 1) until it fits the caps for `n` primitives.
std::array<int, 3> cap_resolution(std::array<int, 3> res, size_t n);

/// Uniform grid over any primitive set.
class UniformGrid final : public Accelerator {
 public:
  /// Reads lambda, res and mailbox from `params` (see the file comment); throws Error on bad
  /// values.
  explicit UniformGrid(const ParamList& params);
  std::string name() const override { return name_; }
  void build(const PrimitiveSet& prims) override;
  bool intersect(const Ray& ray, Hit& hit) const override;
  bool occluded(const Ray& ray) const override;
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const override;
  AccelStats stats() const override { return stats_; }

  /// Cells per axis of the last build (0 when nothing was built).
  std::array<int, 3> resolution() const { return res_; }
  /// The box the cells divide.
  const Bounds3& grid_bounds() const { return box_; }
  /// The box of cell (x, y, z), as the build tested overlap against it.
  Bounds3 cell_bounds(int x, int y, int z) const;
  /// Primitive ids referenced by cell (x, y, z), ascending.
  std::span<const uint32_t> cell(int x, int y, int z) const;

 private:
  /// Sets the grid box, the resolution and the cell sizes for the primitive boxes `refs` (union
  /// `bounds`); returns the number of candidate cells of all the boxes.
  double choose_resolution(std::span<const PrimRef> refs, const Bounds3& bounds);
  /// The range of cells [c0, c1] a primitive's box (grown by more than any cell's pad) touches.
  void candidates(const PrimRef& r, int c0[3], int c1[3]) const;
  /// Calls f(cell index) for every cell primitive `r` overlaps.
  template <class F>
  void for_each_cell(const PrimitiveSet& prims, const PrimRef& r, F&& f) const;
  /// The count and fill passes into the CSR arrays, the occupancy bits and the copied triangles.
  void fill_cells(const PrimitiveSet& prims, std::span<const PrimRef> refs);
  template <bool kAnyHit, bool kTriangles, int kMailbox, class Cost = NoCost>
  bool traverse(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;
  template <bool kAnyHit, class Cost = NoCost>
  bool dispatch(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;

  std::string name_;
  double lambda_ = 1.0;
  std::array<int, 3> fixed_res_{0, 0, 0};  ///< all zero: derive from lambda
  int mailbox_ = 16;
  bool copy_ = true;
  const PrimitiveSet* prims_ = nullptr;
  Bounds3 box_;
  std::array<int, 3> res_{0, 0, 0};
  Vec3 cell_size_, inv_cell_size_;
  Vec3 cand_pad_;  ///< growth of a primitive's box when listing its candidate cells
  /// Cells + 1 entries; cell c holds ids_[offsets_[c], offsets_[c + 1]).
  std::vector<uint32_t, ArrayAllocator<uint32_t>> offsets_;
  std::vector<uint32_t, ArrayAllocator<uint32_t>> ids_;
  /// Triangle-only sets: three vertices per reference, in cell order, or empty.
  std::vector<Vec3, ArrayAllocator<Vec3>> tris_;
  std::vector<uint64_t> occupied_;  ///< bit c set when cell c holds any primitive
  float max_extent_ = 0;  ///< the largest extent of a primitive box (cull_slack, hit.h)
  AccelStats stats_;
};

}  // namespace penumbra
