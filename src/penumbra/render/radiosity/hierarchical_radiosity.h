#pragma once
/// Hierarchical radiosity (Hanrahan, Salzman, Aupperle 1991, "A Rapid Hierarchical Radiosity
/// Algorithm"): each top-level patch is a quadtree, energy moves along links chosen by a BF
/// refinement oracle at the level the oracle allows, and a gather / push-pull iteration solves
/// the system without an n^2 matrix.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"
#include "penumbra/render/radiosity/radiosity_mesh.h"

namespace penumbra {

/// Parameters of the hierarchical solve.
struct HierarchicalOptions {
  /// BF oracle: the link q -> p is accepted when max_channel(rho_p) lum(B_q) max(F_pq, F_qp)
  /// <= epsilon mean lum(B), i.e. when all it can carry is below epsilon of the scene's mean
  /// radiosity (area average over all patches; before the first solve, of the emission).
  float epsilon = 3e-3f;
  /// A node is split only while its children keep at least this area (0: total area * 1e-5).
  float min_area = 0;
  /// Each new link integrates its form factor at m x m points of the receiver (m = link_grid),
  /// each with one visibility ray to a point of the source.
  int link_grid = 2;
  double tolerance = 1e-4;   ///< stop gathering when the largest leaf change / max lum(E) is below
  int max_iterations = 200;  ///< gather / push-pull iterations per refinement round
  int refine_rounds = 3;     ///< BF re-refinement rounds with the current solution (Hanrahan et
                             ///< al. 1991, section 5), each followed by a solve; 0 = link once
  size_t max_nodes = size_t(1) << 24;  ///< node budget: at it, nodes are linked rather than split
};

/// What the solve built and how long it took.
struct HierarchicalStats {
  size_t nodes = 0, leaves = 0, links = 0;
  size_t memory_bytes = 0;     ///< nodes, radiosity arrays and links (capacity)
  size_t visibility_rays = 0;  ///< calls of the visibility function
  int iterations = 0;          ///< gather / push-pull iterations, all rounds
  int rounds = 0;              ///< link refinements done (the first one included)
  double refine_seconds = 0, solve_seconds = 0, seconds = 0;
};

/// One leaf of a patch's quadtree, for display.
struct HierarchicalLeaf {
  uint32_t top = 0;     ///< the top-level patch it belongs to
  uint8_t corners = 3;  ///< 3 (triangle) or 4 (parallelogram)
  Vec3 p[4];            ///< corners, counter-clockwise seen from the patch's normal
  float area = 0;
  Rgb b;  ///< radiosity
};

/// The hierarchical solution over a list of top-level patches.
class HierarchicalRadiosity {
 public:
  /// Fraction of the segment between two surface points that is unoccluded, in [0, 1]. Called
  /// concurrently from several threads; the points lie on the surfaces, so the function should
  /// ignore hits near its ends. An empty function means "everything visible".
  using Visibility = std::function<float(Vec3 a, Vec3 b)>;

  /// Builds the quadtrees and links of `patches` (planar triangles and parallelograms, corners
  /// from `vertices`) and solves. The top level should be coarse (walls, primitives): every pair
  /// of mutually facing top-level patches costs at least one link, k^2 for k patches.
  static HierarchicalRadiosity solve(const std::vector<RadiosityElement>& patches,
                                     const std::vector<Vec3>& vertices,
                                     const Visibility& visibility,
                                     const HierarchicalOptions& options);

  /// Radiosity of each top-level patch: the area average of its leaves.
  const std::vector<Rgb>& patch_radiosity() const { return patch_b_; }
  /// Radiosity of top-level patch `top` at the point p on it (that of the leaf containing p).
  Rgb radiosity_at(uint32_t top, Vec3 p) const;
  /// Radiosity of top-level patch `top` gathered at the point p itself: E + rho times the sum,
  /// over the links of the leaf containing p and of its ancestors, of the point form factor from
  /// p to the link's source (times its visibility from p: a ray to the source's centroid where the
  /// link is partly occluded) times the source's radiosity. The
  /// leaves' constant B is the mean of this over the leaf; where a leaf gathers from many links
  /// whose form factors all vary across it the same way (a ceiling lit by the floor), the point
  /// value keeps that gradient, which the leaf's constant loses.
  Rgb gathered_at(uint32_t top, Vec3 p) const;
  /// All leaves, patch by patch.
  std::vector<HierarchicalLeaf> leaves() const;
  /// Largest relative leaf change per gather / push-pull iteration, all rounds.
  const std::vector<double>& changes() const { return changes_; }
  const HierarchicalStats& stats() const { return stats_; }

 private:
  /// A quadtree node: the point o + s e1 + t e2 with (s, t) in the unit square (parallelogram)
  /// or the unit triangle s + t <= 1.
  struct Node {
    Vec3 o, e1, e2;
    float area = 0;
    uint32_t top = 0;
    uint32_t child = UINT32_MAX;  ///< first of 4 consecutive children, UINT32_MAX for a leaf
  };
  /// Per top-level patch: what all its nodes share.
  struct Patch {
    Vec3 normal;
    Rgb rho, emission;
    uint8_t corners = 3;
  };
  /// A gathering link: receiver <- source, with the visibility-weighted form factor F_rs.
  struct Link {
    uint32_t receiver = 0, source = 0;
    float ff = 0, vis = 0;
    float ff_vis = 1;  ///< ff over its unoccluded value: the form-factor-weighted visibility
  };
  /// The leaf of `top` containing p, and the nodes on the way to it (the root first).
  uint32_t descend(uint32_t top, Vec3 p, uint32_t path[64], int& depth) const;
  /// The oracle's view of a pair.
  struct Estimate {
    bool interacts = false, straddles = false;
    float f_pq = 0, f_qp = 0;
    float spread = 0;  ///< largest spread of the point form factors over either side's points
  };

  Vec3 centroid(uint32_t n) const;
  int corner_points(uint32_t n, Vec3 out[4]) const;
  float point_to_node_ff(Vec3 x, Vec3 nx, uint32_t q) const;
  Estimate estimate(uint32_t p, uint32_t q) const;
  bool splittable(uint32_t n) const;
  void split(uint32_t n);
  void update_threshold();
  bool accept(uint32_t p, uint32_t q, const Estimate& e) const;
  void refine(uint32_t p, uint32_t q, std::vector<Link>& out, bool force = false);
  void evaluate_links(std::vector<Link>& links, size_t first, const Visibility& vis);
  void index_links();
  double gather_push_pull();
  Rgb push_pull(uint32_t n, Rgb down, double& change);

  HierarchicalOptions opt_;
  Visibility visibility_;  ///< kept for gathered_at
  std::vector<Patch> patches_;
  std::vector<Node> nodes_;  ///< nodes [0, patches) are the roots
  std::vector<Rgb> b_, gather_;
  std::vector<Link> links_;           ///< sorted by receiver
  std::vector<uint32_t> link_begin_;  ///< links of node n: [link_begin_[n], link_begin_[n + 1])
  std::vector<Rgb> patch_b_;
  std::vector<double> changes_;
  HierarchicalStats stats_;
  float min_area_ = 0;
  double eps_abs_ = 0;  ///< epsilon * the mean lum(B), see update_threshold
  double total_area_ = 0;
  double e_scale_ = 1;  ///< max lum(E), the normaliser of changes
};

}  // namespace penumbra
