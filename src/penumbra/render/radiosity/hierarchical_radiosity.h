#pragma once
/// Hierarchical radiosity (Hanrahan, Salzman, Aupperle 1991, "A Rapid Hierarchical Radiosity
/// Algorithm"): each top-level patch is a quadtree, energy moves along links chosen by a BF
/// refinement oracle at the level the oracle allows, and a gather / push-pull iteration solves
/// the system without an n^2 matrix. With clustering (Smits, Arvo, Greenberg 1994, "A Clustering
/// Algorithm for Radiosity in Complex Environments") a binary cluster tree sits above the
/// top-level patches, linking starts from the root cluster, and distant groups of patches
/// exchange energy through single links, so that the links grow about linearly with the patches.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"
#include "penumbra/render/radiosity/cluster_tree.h"
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
  /// Clustering: a cluster tree above the top-level patches when there are more than
  /// `cluster_min_patches` of them (below that every pair of top-level patches is linked, as
  /// without clustering; 64 keeps the Cornell box's 48 patches exactly as before).
  bool clusters = true;
  size_t cluster_min_patches = 64;
};

/// What the solve built and how long it took.
struct HierarchicalStats {
  size_t patches = 0;   ///< top-level patches
  size_t clusters = 0;  ///< clusters above them (0 without clustering)
  size_t nodes = 0, leaves = 0, links = 0;
  size_t cluster_links = 0;    ///< links with a cluster at one end or both (part of `links`)
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
  /// from `vertices`) and solves. Without clustering every pair of mutually facing top-level
  /// patches costs at least one link, k^2 for k patches; with it (options.clusters) the links
  /// start from the root cluster and grow about linearly with k.
  static HierarchicalRadiosity solve(const std::vector<RadiosityElement>& patches,
                                     const std::vector<Vec3>& vertices,
                                     const Visibility& visibility,
                                     const HierarchicalOptions& options);

  /// Radiosity of each top-level patch: the area average of its leaves.
  const std::vector<Rgb>& patch_radiosity() const { return patch_b_; }
  /// Radiosity of top-level patch `top` at the point p on it (that of the leaf containing p).
  Rgb radiosity_at(uint32_t top, Vec3 p) const;
  /// Radiosity of top-level patch `top` gathered at the point p itself: E + rho times the sum,
  /// over the links of the leaf containing p and of its ancestors (its clusters included), of
  /// the point form factor from p to the link's source (times its visibility from p: a ray to
  /// the source's centroid where a patch-to-patch link is partly occluded, the link's mean
  /// visibility for a cluster link) times the source's radiosity as seen from p. The leaves'
  /// constant B is the mean of this over the leaf; where a leaf gathers from many links whose
  /// form factors all vary across it the same way (a ceiling lit by the floor), the point value
  /// keeps that gradient, which the leaf's constant loses.
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
  /// A gathering link: receiver <- source, with the visibility-weighted form factor F_rs. Either
  /// end may be a cluster (ClusterTree::kClusterBit | cluster index) instead of a node.
  struct Link {
    uint32_t receiver = 0, source = 0;
    float ff = 0, vis = 0;
    float ff_vis = 1;   ///< ff over its unoccluded value: the form-factor-weighted visibility
    float pa = 0;       ///< a cluster source's projected area toward the receiver
    uint32_t data = 0;  ///< a cluster link's words in link_data_ (see link_words)
  };
  /// New links from a refinement, by the kind of their receiver.
  struct NewLinks {
    std::vector<Link> nodes, clusters;
  };
  /// The leaf of `top` containing p, and the nodes on the way to it (the root first).
  uint32_t descend(uint32_t top, Vec3 p, uint32_t path[64], int& depth) const;
  /// The oracle's view of a pair.
  struct Estimate {
    bool interacts = false, straddles = false;
    float f_pq = 0, f_qp = 0;
    float spread = 0;  ///< largest spread of the point form factors over either side's points
  };
  /// The cluster oracle's view of a pair with a cluster at one end or both.
  struct ClusterEstimate {
    bool interacts = false;
    double transport = 0;    ///< bound on rho_r B_s F_rs
    double form_factor = 0;  ///< bound on F_rs
    float radius_r = 0, radius_s = 0;
  };
  /// One side of a pair for the cluster oracle: over its members that can face the other side,
  /// a bound on sum lum(B) A cos, the largest lum(B) and the largest max_channel(rho).
  struct SideBound {
    bool facing = false;
    double flux = 0, area = 0;
    float b_max = 0, rho_max = 0;
  };
  /// Where a node or cluster lies, for the cluster oracle.
  struct Extent {
    Bounds3 box;
    Vec3 centre;
    float radius = 0;  ///< half the box's diagonal
  };

  // Patches (hierarchical_radiosity.cpp).
  /// Points of a node's m x m quadrature rule, (s, t) pairs.
  static void rule_points(int corners, int m, std::vector<float>& st);
  Vec3 centroid(uint32_t n) const;
  int corner_points(uint32_t n, Vec3 out[4]) const;
  float point_to_node_ff(Vec3 x, Vec3 nx, uint32_t q) const;
  Estimate estimate(uint32_t p, uint32_t q) const;
  bool splittable(uint32_t n) const;
  void split(uint32_t n);
  void update_threshold();
  bool accept(uint32_t p, uint32_t q, const Estimate& e) const;
  double carried(uint32_t p, uint32_t q, const Estimate& e) const;
  void refine(uint32_t p, uint32_t q, std::vector<Link>& out, bool force = false);
  /// Appends l to out, refusing (core/memory_limit.h) a refinement whose links and nodes would
  /// exceed the memory limit: checked as out's size passes each power of two from 2^16.
  void add_link(std::vector<Link>& out, const Link& l) const;
  void evaluate_links(std::vector<Link>& links, size_t first, const Visibility& vis);
  void index_links();
  double gather_push_pull();
  Rgb push_pull(uint32_t n, Rgb down, double& change);
  void rerefine(NewLinks& kept, NewLinks& fresh);

  // Clusters (hierarchical_clusters.cpp).
  static bool is_cluster(uint32_t ref) { return (ref & ClusterTree::kClusterBit) != 0; }
  const ClusterTree::Cluster& cluster(uint32_t ref) const {
    return tree_.clusters()[ref & ~ClusterTree::kClusterBit];
  }
  void build_clusters();
  Extent extent(uint32_t ref) const;
  SideBound side_bound(uint32_t ref, Vec3 dir, float cos_b, float sin_b,
                       const Bounds3& other) const;
  bool receives(uint32_t ref) const;
  bool sends(uint32_t ref) const;
  ClusterEstimate estimate_cluster(uint32_t r, uint32_t s) const;
  bool admissible(const ClusterEstimate& e) const;
  void link_self(uint32_t cluster_ref, NewLinks& out);
  void link_refs(uint32_t r, uint32_t s, NewLinks& out);
  int cluster_samples(uint32_t ref, Vec3 dir, int count, uint32_t* out, float& projected) const;
  int source_samples(uint32_t s, Vec3 dir, float dist, int count, uint32_t* words, Vec3* exposed,
                     float& projected, const Visibility& vis) const;
  size_t link_words(const Link& l) const;
  void allocate_link_data(std::vector<Link>& links, size_t first);
  void evaluate_from_cluster(Link& l, const std::vector<float>& st, int count,
                             const Visibility& vis);
  void evaluate_cluster_links(std::vector<Link>& links, size_t first, const Visibility& vis);
  Rgb link_source_b(const Link& l) const;
  float member_ff(const Link& l, Vec3 x, Vec3 nx) const;
  bool member_visible(const Link& l, uint32_t cluster_index, uint32_t patch) const;
  void gather_clusters();

  HierarchicalOptions opt_;
  Visibility visibility_;  ///< kept for gathered_at
  std::vector<Patch> patches_;
  std::vector<Node> nodes_;  ///< nodes [0, patches) are the roots
  std::vector<Rgb> b_, gather_;
  std::vector<Link> links_;           ///< node receivers, sorted by receiver
  std::vector<uint32_t> link_begin_;  ///< links of node n: [link_begin_[n], link_begin_[n + 1])
  std::vector<Rgb> patch_b_;
  std::vector<double> changes_;
  HierarchicalStats stats_;
  float min_area_ = 0;
  double eps_abs_ = 0;  ///< epsilon * the mean lum(B), see update_threshold
  double total_area_ = 0;
  double e_scale_ = 1;  ///< max lum(E), the normaliser of changes

  // Clustering; all empty without it.
  ClusterTree tree_;
  std::vector<Link> cluster_links_;           ///< cluster receivers, sorted by receiver
  std::vector<uint32_t> cluster_link_begin_;  ///< per cluster, as link_begin_
  std::vector<Rgb> cluster_link_b_;     ///< per cluster link: its source's B seen by the receiver
  std::vector<uint8_t> cluster_flags_;  ///< per cluster: kReceives | kSends of any member
  /// Per cluster link, at Link::data: with a cluster source, its link_grid^2 sample members
  /// (kExposed set where the member is not hidden by its own cluster toward the receiver); then,
  /// with a cluster receiver, one bit per member (in members() order): it faces the source and
  /// sees it.
  std::vector<uint32_t> link_data_;
};

}  // namespace penumbra
