#include "penumbra/render/radiosity/hierarchical_radiosity.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "penumbra/core/dvec3.h"
#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"

namespace penumbra {

namespace {

constexpr uint32_t kLeaf = UINT32_MAX;

double lum(Rgb c) {
  return c.luminance();
}

}  // namespace

// Points of a node's m x m quadrature rule in (s, t): cell centres of a parallelogram, the
// centroids of the m^2 similar sub-triangles of a triangle.
void HierarchicalRadiosity::rule_points(int corners, int m, std::vector<float>& st) {
  st.clear();
  const float inv = 1.f / float(m);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      if (corners == 4) {
        st.push_back((float(i) + 0.5f) * inv), st.push_back((float(j) + 0.5f) * inv);
      } else if (i + j <= m - 1) {
        st.push_back((float(i) + 1.f / 3) * inv), st.push_back((float(j) + 1.f / 3) * inv);
        if (i + j <= m - 2)
          st.push_back((float(i) + 2.f / 3) * inv), st.push_back((float(j) + 2.f / 3) * inv);
      }
    }
  }
}

Vec3 HierarchicalRadiosity::centroid(uint32_t n) const {
  const Node& d = nodes_[n];
  const float w = patches_[d.top].corners == 4 ? 0.5f : 1.f / 3;
  return d.o + (d.e1 + d.e2) * w;
}

int HierarchicalRadiosity::corner_points(uint32_t n, Vec3 out[4]) const {
  const Node& d = nodes_[n];
  if (patches_[d.top].corners == 4) {
    out[0] = d.o, out[1] = d.o + d.e1, out[2] = d.o + d.e1 + d.e2, out[3] = d.o + d.e2;
    return 4;
  }
  out[0] = d.o, out[1] = d.o + d.e1, out[2] = d.o + d.e2;
  return 3;
}

// Form factor from a differential area at x (normal nx) to node q, unoccluded: Lambert's
// contour formula (see Baum, Rushmeier, Winget 1989, "Improving Radiosity Solutions Through the
// Use of Analytically Determined Form Factors"), with q clipped to the half-space above x so that
// the cosine at x is never negative. Exact for the polygon, finite even next to a shared edge,
// which the point-to-disc approximation is not.
float HierarchicalRadiosity::point_to_node_ff(Vec3 x, Vec3 nx, uint32_t q) const {
  const Node& d = nodes_[q];
  const Vec3 nq = patches_[d.top].normal;
  if (dot(nq, x - d.o) <= 0) return 0;  // x is behind q, which emits to its front only
  Vec3 c[4];
  const int k = corner_points(q, c);
  // Sutherland-Hodgman against the plane through x with normal nx.
  DVec3 poly[5];
  int m = 0;
  for (int i = 0; i < k; ++i) {
    const Vec3 a = c[i], b = c[(i + 1) % k];
    const double da = dot(nx, a - x), db = dot(nx, b - x);
    if (da >= 0) poly[m++] = DVec3(a - x);
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      poly[m++] = DVec3(a - x) + (DVec3(b - x) - DVec3(a - x)) * t;
    }
  }
  if (m < 3) return 0;
  const DVec3 n(nx);
  double sum = 0;
  for (int i = 0; i < m; ++i) {
    const DVec3 a = poly[i], b = poly[(i + 1) % m];
    const DVec3 g = cross(a, b);
    const double len = length(g);
    if (len <= 1e-30) continue;
    sum += std::atan2(len, dot(a, b)) * dot(n, g) / len;
  }
  return static_cast<float>(std::fabs(sum) / (2 * std::numbers::pi));
}

// Whether p and q face each other, whether either straddles the other's plane (then the centroid
// estimate says little), and F_pq, F_qp from the centroids.
HierarchicalRadiosity::Estimate HierarchicalRadiosity::estimate(uint32_t p, uint32_t q) const {
  Estimate e;
  Vec3 cp[4], cq[4];
  const int kp = corner_points(p, cp), kq = corner_points(q, cq);
  const float eps = 1e-5f * std::sqrt(std::max(nodes_[p].area, nodes_[q].area));
  // Corners of `c` against the plane (o, n): any strictly in front, any strictly behind.
  const auto side = [eps](const Vec3* c, int k, Vec3 o, Vec3 n, bool& front, bool& behind) {
    front = behind = false;
    for (int i = 0; i < k; ++i) {
      const float s = dot(n, c[i] - o);
      front |= s > eps, behind |= s < -eps;
    }
  };
  const Vec3 np = patches_[nodes_[p].top].normal, nq = patches_[nodes_[q].top].normal;
  bool q_front, q_behind, p_front, p_behind;
  side(cq, kq, cp[0], np, q_front, q_behind);
  side(cp, kp, cq[0], nq, p_front, p_behind);
  if (!q_front || !p_front) return e;
  e.interacts = true;
  e.straddles = q_behind || p_behind;
  e.f_pq = point_to_node_ff(centroid(p), np, q);
  e.f_qp = point_to_node_ff(centroid(q), nq, p);
  // The spread of the point form factors over each side's corners and centroid: how far a
  // transfer taken as uniform over the receiver (and from a source of uniform radiosity) can be
  // from the true one.
  float lo = e.f_pq, hi = e.f_pq;
  for (int i = 0; i < kp; ++i) {
    const float f = point_to_node_ff(cp[i], np, q);
    lo = std::min(lo, f), hi = std::max(hi, f);
  }
  e.spread = hi - lo;
  lo = hi = e.f_qp;
  for (int i = 0; i < kq; ++i) {
    const float f = point_to_node_ff(cq[i], nq, p);
    lo = std::min(lo, f), hi = std::max(hi, f);
  }
  e.spread = std::max(e.spread, hi - lo);
  return e;
}

bool HierarchicalRadiosity::splittable(uint32_t n) const {
  return nodes_[n].area * 0.25f >= min_area_ && nodes_.size() + 4 <= opt_.max_nodes;
}

// Four children from the edge midpoints: parallelograms into 4 parallelograms, triangles into 3
// corner triangles and the inverted middle one (s' = 1 - 2s, t' = 1 - 2t), all of a quarter area.
void HierarchicalRadiosity::split(uint32_t n) {
  if (nodes_[n].child != kLeaf) return;
  const Node d = nodes_[n];
  const Vec3 h1 = d.e1 * 0.5f, h2 = d.e2 * 0.5f;
  const bool quad = patches_[d.top].corners == 4;
  Node c{d.o, h1, h2, d.area * 0.25f, d.top, kLeaf};
  const uint32_t first = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back(c);
  c.o = d.o + h1, nodes_.push_back(c);
  c.o = d.o + h2, nodes_.push_back(c);
  if (quad) {
    c.o = d.o + h1 + h2;
  } else {
    c.o = d.o + h1 + h2, c.e1 = -h1, c.e2 = -h2;
  }
  nodes_.push_back(c);
  nodes_[n].child = first;
  // Children start from the parent's radiosity, so that the oracle can judge them at once.
  for (int i = 0; i < 4; ++i) b_.push_back(b_[n]), gather_.push_back(Rgb());
}

// The oracle's threshold: epsilon times the scene's mean radiosity, the area average of lum(B)
// over all top-level patches (before the first solve B = E, the mean emitted radiosity). Relative
// to the brightest emitter instead, a small bright light (the Cornell box's is 150 times the walls'
// radiosity) let links carry 12 % of a wall's radiosity at epsilon = 1e-3 and left the ceiling
// 20 % dark.
void HierarchicalRadiosity::update_threshold() {
  double sum = 0;
  for (size_t t = 0; t < patches_.size(); ++t) sum += double(nodes_[t].area) * lum(b_[t]);
  const double mean = total_area_ > 0 ? sum / total_area_ : 0;
  eps_abs_ = opt_.epsilon * (mean > 0 ? mean : e_scale_);
}

// The BF oracle (Hanrahan et al. 1991, section 5): all the link could carry to p is below the
// threshold.
bool HierarchicalRadiosity::accept(uint32_t p, uint32_t q, const Estimate& e) const {
  if (e.straddles) return false;
  if (carried(p, q, e) <= eps_abs_) return true;  // carries almost nothing
  return patches_[nodes_[p].top].rho.max_channel() * lum(b_[q]) * e.spread <=
         eps_abs_;  // or carries it almost uniformly
}

// The most the link q -> p can carry to p (unoccluded): rho_p lum(B_q) max(F_pq, F_qp).
double HierarchicalRadiosity::carried(uint32_t p, uint32_t q, const Estimate& e) const {
  return patches_[nodes_[p].top].rho.max_channel() * lum(b_[q]) * std::max(e.f_pq, e.f_qp);
}

void HierarchicalRadiosity::add_link(std::vector<Link>& out, const Link& l) const {
  const size_t n = out.size() + 1;
  if (n >= (size_t(1) << 16) && (n & (n - 1)) == 0) {
    // The links of every list at this size again (a vector's growth), and the nodes so far.
    const double bytes = 2.0 * double(n + links_.size() + cluster_links_.size()) * sizeof(Link) +
                         double(nodes_.size()) * sizeof(Node);
    check_memory(bytes, fmt::format("hierarchical radiosity: a refinement to {} links", n),
                 "raise epsilon or lower link_grid");
  }
  out.push_back(l);
}

// Refine(p, q) of Hanrahan et al. 1991: link p <- q if the oracle accepts or nothing can be split,
// else split the side that looks larger from the other (q when F_pq >= F_qp) and recurse;
// `force` splits once whatever the oracle says (a link across a shadow boundary).
void HierarchicalRadiosity::refine(uint32_t p, uint32_t q, std::vector<Link>& out, bool force) {
  const Estimate e = estimate(p, q);
  if (!e.interacts) return;
  const bool can_p = splittable(p), can_q = splittable(q);
  if ((!can_p && !can_q) || (!force && accept(p, q, e))) {
    add_link(out, {p, q, -1.f, 0.f});  // form factor evaluated later, in parallel
    return;
  }
  bool split_q = e.straddles ? nodes_[q].area >= nodes_[p].area : e.f_pq >= e.f_qp;
  if (!can_p) split_q = true;
  if (!can_q) split_q = false;
  if (split_q) {
    split(q);
    const uint32_t c = nodes_[q].child;
    for (uint32_t i = 0; i < 4; ++i) refine(p, c + i, out);
  } else {
    split(p);
    const uint32_t c = nodes_[p].child;
    for (uint32_t i = 0; i < 4; ++i) refine(c + i, q, out);
  }
}

// F_pq of each new link (ff < 0) as the mean over m x m points x of p of the analytic point-to-q
// form factor, each weighted by the visibility of one ray from x to a point of q (Hanrahan et
// al. use a few rays per link too). Links are independent: parallel and deterministic.
void HierarchicalRadiosity::evaluate_links(std::vector<Link>& links, size_t first,
                                           const Visibility& vis) {
  const int m = std::max(1, opt_.link_grid);
  std::vector<float> st_tri, st_quad;
  rule_points(3, m, st_tri);
  rule_points(4, m, st_quad);
  const size_t count = size_t(m) * m;
  allocate_link_data(links, first);
  parallel_for(
      links.size() - first,
      [&](size_t k) {
        Link& l = links[first + k];
        const Node& p = nodes_[l.receiver];
        const std::vector<float>& sp = patches_[p.top].corners == 4 ? st_quad : st_tri;
        if (is_cluster(l.source)) return evaluate_from_cluster(l, sp, int(count), vis);
        const Node& q = nodes_[l.source];
        const std::vector<float>& sq = patches_[q.top].corners == 4 ? st_quad : st_tri;
        const Vec3 np = patches_[p.top].normal;
        double ff = 0, seen = 0, open = 0;
        for (size_t s = 0; s < count; ++s) {
          const Vec3 x = p.o + p.e1 * sp[2 * s] + p.e2 * sp[2 * s + 1];
          // Pair x with the mirrored point of q, so that rays do not all run parallel.
          const size_t r = count - 1 - s;
          const Vec3 y = q.o + q.e1 * sq[2 * r] + q.e2 * sq[2 * r + 1];
          const float v = vis ? vis(x, y) : 1.f;
          const double f = point_to_node_ff(x, np, l.source);
          ff += f * v;
          open += f;
          seen += v;
        }
        l.ff = static_cast<float>(ff / double(count));
        l.vis = static_cast<float>(seen / double(count));
        l.ff_vis = open > 0 ? static_cast<float>(ff / open) : l.vis;
      },
      16);
  if (vis) stats_.visibility_rays += (links.size() - first) * count;
}

// Sorts links by receiver (stable: creation order within a receiver, so the sums are the same
// at any thread count) and indexes them per node and per cluster.
void HierarchicalRadiosity::index_links() {
  const auto by_receiver = [](const Link& a, const Link& b) { return a.receiver < b.receiver; };
  const auto index = [](const std::vector<Link>& links, size_t n, std::vector<uint32_t>& begin) {
    begin.assign(n + 1, 0);
    for (const Link& l : links) ++begin[(l.receiver & ~ClusterTree::kClusterBit) + 1];
    for (size_t i = 0; i < n; ++i) begin[i + 1] += begin[i];
  };
  for (std::vector<Link>* links : {&links_, &cluster_links_})
    std::stable_sort(links->begin(), links->end(), by_receiver);
  // Cluster link data in the links' new order, without that of refined links.
  std::vector<uint32_t> data;
  data.reserve(link_data_.size());
  for (std::vector<Link>* links : {&links_, &cluster_links_})
    for (Link& l : *links) {
      const size_t words = link_words(l);
      const uint32_t at = static_cast<uint32_t>(data.size());
      data.insert(data.end(), link_data_.begin() + l.data, link_data_.begin() + l.data + words);
      l.data = at;
    }
  link_data_ = std::move(data);
  index(links_, nodes_.size(), link_begin_);
  index(cluster_links_, tree_.clusters().size(), cluster_link_begin_);
  cluster_link_b_.assign(cluster_links_.size(), Rgb());
}

// PushPull of Hanrahan et al. 1991: the gathered radiosity of the ancestors flows down to the
// leaves (B = E + all gathered above), and each node's B is the area average of its children
// (equal quarters). Returns the node's new B; `change` collects the largest leaf change.
Rgb HierarchicalRadiosity::push_pull(uint32_t n, Rgb down, double& change) {
  down += gather_[n];
  Rgb b;
  const uint32_t c = nodes_[n].child;
  if (c == kLeaf) {
    b = patches_[nodes_[n].top].emission + down;
    const Rgb d = b - b_[n];
    change =
        std::max(change, double(Rgb(std::fabs(d.r), std::fabs(d.g), std::fabs(d.b)).luminance()));
  } else {
    for (uint32_t i = 0; i < 4; ++i) b += push_pull(c + i, down, change);
    b *= 0.25f;
  }
  b_[n] = b;
  return b;
}

// One Jacobi-style iteration: every node gathers over its links from the current B (parallel
// over nodes), the top-level patches over their clusters' links, then push-pull per patch tree
// (parallel over patches: trees are disjoint).
double HierarchicalRadiosity::gather_push_pull() {
  parallel_for(
      nodes_.size(),
      [&](size_t n) {
        Rgb sum;
        for (uint32_t l = link_begin_[n]; l < link_begin_[n + 1]; ++l) {
          const Link& link = links_[l];
          sum += link_source_b(link) * link.ff;
        }
        gather_[n] = patches_[nodes_[n].top].rho * sum;
      },
      256);
  gather_clusters();
  std::vector<double> change(patches_.size(), 0.0);
  parallel_for(patches_.size(),
               [&](size_t t) { push_pull(static_cast<uint32_t>(t), Rgb(), change[t]); });
  return *std::max_element(change.begin(), change.end()) / e_scale_;
}

// Re-refinement (Hanrahan et al. 1991, section 5): the links that the oracle rejects with the
// current B are refined into `fresh`, the others go to `kept` with their form factors. The
// oracle only reads, so it judges all links in parallel; the refinement, which adds nodes,
// then runs in link order, as it would alone.
void HierarchicalRadiosity::rerefine(NewLinks& kept, NewLinks& fresh) {
  constexpr uint8_t kReject = 1, kPartial = 2;
  std::vector<uint8_t> verdict(links_.size() + cluster_links_.size(), 0);
  parallel_for(
      verdict.size(),
      [&](size_t i) {
        const bool node_receiver = i < links_.size();
        const Link& l = node_receiver ? links_[i] : cluster_links_[i - links_.size()];
        if (!node_receiver || is_cluster(l.source)) {
          verdict[i] = admissible(estimate_cluster(l.receiver, l.source)) ? 0 : kReject;
          return;
        }
        const Estimate e = estimate(l.receiver, l.source);
        // A partly occluded link that carries more than the threshold crosses a shadow
        // boundary: refine it, whatever the oracle says of its unoccluded form factors.
        const bool partial = l.vis > 0 && l.vis < 1 && carried(l.receiver, l.source, e) > eps_abs_;
        verdict[i] =
            uint8_t((accept(l.receiver, l.source, e) ? 0 : kReject) | (partial ? kPartial : 0));
      },
      256);
  kept.nodes.reserve(links_.size());
  kept.clusters.reserve(cluster_links_.size());
  for (size_t i = 0; i < links_.size(); ++i) {
    const Link& l = links_[i];
    if (is_cluster(l.source)) {
      if (verdict[i] & kReject)
        link_refs(l.receiver, l.source, fresh);
      else
        kept.nodes.push_back(l);
      continue;
    }
    if ((splittable(l.receiver) || splittable(l.source)) && verdict[i] != 0)
      refine(l.receiver, l.source, fresh.nodes, (verdict[i] & kPartial) != 0);
    else
      kept.nodes.push_back(l);
  }
  for (size_t i = 0; i < cluster_links_.size(); ++i) {
    if (verdict[links_.size() + i] & kReject)
      link_refs(cluster_links_[i].receiver, cluster_links_[i].source, fresh);
    else
      kept.clusters.push_back(cluster_links_[i]);
  }
}

HierarchicalRadiosity HierarchicalRadiosity::solve(const std::vector<RadiosityElement>& patches,
                                                   const std::vector<Vec3>& vertices,
                                                   const Visibility& visibility,
                                                   const HierarchicalOptions& options) {
  Timer total;
  HierarchicalRadiosity h;
  h.opt_ = options;
  h.visibility_ = visibility;
  const size_t k = patches.size();
  // Roots: one node per top-level patch.
  double total_area = 0, e_max = 0;
  for (size_t i = 0; i < k; ++i) {
    const RadiosityElement& el = patches[i];
    for (int c = 0; c < el.corners; ++c)
      if (el.v[c] >= vertices.size())
        throw Error("hierarchical radiosity: patch " + std::to_string(i) + " has vertex index " +
                    std::to_string(el.v[c]) + " of " + std::to_string(vertices.size()));
    if (el.corners != 3 && el.corners != 4)
      throw Error("hierarchical radiosity: patch " + std::to_string(i) + " has " +
                  std::to_string(el.corners) + " corners (3 or 4 expected)");
    const Vec3 o = vertices[el.v[0]];
    const Vec3 e1 = vertices[el.v[1]] - o;
    const Vec3 e2 = vertices[el.v[el.corners == 4 ? 3 : 2]] - o;
    const float area = length(cross(e1, e2)) * (el.corners == 4 ? 1.f : 0.5f);
    h.patches_.push_back({el.normal, el.rho, el.emission, el.corners});
    h.nodes_.push_back({o, e1, e2, area, static_cast<uint32_t>(i), kLeaf});
    h.b_.push_back(el.emission);
    h.gather_.push_back(Rgb());
    total_area += area;
    e_max = std::max(e_max, lum(el.emission));
  }
  h.min_area_ = options.min_area > 0 ? options.min_area : static_cast<float>(total_area * 1e-5);
  h.e_scale_ = e_max > 0 ? e_max : 1.0;
  h.total_area_ = total_area;
  if (options.clusters && k > options.cluster_min_patches) h.build_clusters();
  h.update_threshold();

  // Initial linking, judged by B = E: from the root cluster's self-link, or of every pair of
  // top-level patches (a receiver that reflects nothing needs no links, a source that neither
  // emits nor reflects never sends anything: both are skipped).
  Timer timer;
  NewLinks initial;
  if (!h.tree_.empty()) {
    h.link_self(ClusterTree::kClusterBit | 0u, initial);
  } else {
    for (size_t p = 0; p < k; ++p)
      if (h.receives(uint32_t(p)))
        for (size_t q = 0; q < k; ++q)
          if (q != p && h.sends(uint32_t(q))) h.refine(uint32_t(p), uint32_t(q), initial.nodes);
  }
  h.links_ = std::move(initial.nodes);
  h.cluster_links_ = std::move(initial.clusters);
  h.evaluate_links(h.links_, 0, visibility);
  h.evaluate_cluster_links(h.cluster_links_, 0, visibility);
  h.index_links();
  h.stats_.refine_seconds += timer.elapsed_s();
  h.stats_.rounds = 1;

  for (int round = 0;; ++round) {
    // Solve with the current links.
    timer.reset();
    for (int it = 0; it < options.max_iterations; ++it) {
      const double change = h.gather_push_pull();
      h.changes_.push_back(change);
      ++h.stats_.iterations;
      if (change <= options.tolerance) break;
    }
    h.stats_.solve_seconds += timer.elapsed_s();
    if (round >= options.refine_rounds) break;
    h.update_threshold();
    timer.reset();
    NewLinks kept, fresh;
    h.rerefine(kept, fresh);
    const bool changed = !fresh.nodes.empty() || !fresh.clusters.empty();
    if (changed) {
      const size_t first = kept.nodes.size(), first_cluster = kept.clusters.size();
      kept.nodes.insert(kept.nodes.end(), fresh.nodes.begin(), fresh.nodes.end());
      kept.clusters.insert(kept.clusters.end(), fresh.clusters.begin(), fresh.clusters.end());
      h.evaluate_links(kept.nodes, first, visibility);
      h.evaluate_cluster_links(kept.clusters, first_cluster, visibility);
      h.links_ = std::move(kept.nodes);
      h.cluster_links_ = std::move(kept.clusters);
      h.index_links();
      ++h.stats_.rounds;
    }
    h.stats_.refine_seconds += timer.elapsed_s();
    if (!changed) break;
  }

  h.patch_b_.assign(h.b_.begin(), h.b_.begin() + static_cast<std::ptrdiff_t>(k));
  HierarchicalStats& s = h.stats_;
  s.patches = k;
  s.clusters = h.tree_.clusters().size();
  s.nodes = h.nodes_.size();
  s.leaves = static_cast<size_t>(std::count_if(h.nodes_.begin(), h.nodes_.end(),
                                               [](const Node& n) { return n.child == kLeaf; }));
  s.links = h.links_.size() + h.cluster_links_.size();
  s.cluster_links = h.cluster_links_.size() +
                    size_t(std::count_if(h.links_.begin(), h.links_.end(),
                                         [](const Link& l) { return is_cluster(l.source); }));
  s.memory_bytes =
      h.nodes_.capacity() * sizeof(Node) + (h.b_.capacity() + h.gather_.capacity()) * sizeof(Rgb) +
      (h.links_.capacity() + h.cluster_links_.capacity()) * sizeof(Link) +
      (h.link_begin_.capacity() + h.cluster_link_begin_.capacity()) * sizeof(uint32_t) +
      h.patches_.capacity() * sizeof(Patch) + h.tree_.memory_bytes() +
      h.cluster_link_b_.capacity() * sizeof(Rgb) + h.cluster_flags_.capacity() +
      h.link_data_.capacity() * sizeof(uint32_t);
  s.seconds = total.elapsed_s();
  return h;
}

uint32_t HierarchicalRadiosity::descend(uint32_t top, Vec3 x, uint32_t path[64], int& depth) const {
  // (s, t) of x in the root's frame: least squares on the two edges.
  const Node& r = nodes_[top];
  const Vec3 d = x - r.o;
  const double a = dot(r.e1, r.e1), b = dot(r.e1, r.e2), c = dot(r.e2, r.e2);
  const double u = dot(d, r.e1), v = dot(d, r.e2), det = a * c - b * b;
  float s = static_cast<float>((c * u - b * v) / det),
        t = static_cast<float>((a * v - b * u) / det);
  s = std::clamp(s, 0.f, 1.f), t = std::clamp(t, 0.f, 1.f);
  const bool quad = patches_[top].corners == 4;
  if (!quad && s + t > 1) {
    const float sum = s + t;
    s /= sum, t /= sum;
  }
  // Descend to the leaf containing (s, t), mapping it into each child's frame (split's order).
  uint32_t n = top;
  depth = 0;
  path[depth++] = n;
  while (nodes_[n].child != kLeaf && depth < 64) {
    uint32_t i;
    if (quad) {
      i = (s >= 0.5f ? 1u : 0u) + (t >= 0.5f ? 2u : 0u);
      s = 2 * s - (s >= 0.5f ? 1.f : 0.f), t = 2 * t - (t >= 0.5f ? 1.f : 0.f);
    } else if (s >= 0.5f) {
      i = 1, s = 2 * s - 1, t = 2 * t;
    } else if (t >= 0.5f) {
      i = 2, s = 2 * s, t = 2 * t - 1;
    } else if (s + t < 0.5f) {
      i = 0, s = 2 * s, t = 2 * t;
    } else {
      i = 3, s = 1 - 2 * s, t = 1 - 2 * t;
    }
    n = nodes_[n].child + i;
    path[depth++] = n;
  }
  return n;
}

Rgb HierarchicalRadiosity::radiosity_at(uint32_t top, Vec3 x) const {
  if (top >= patches_.size()) return Rgb();
  uint32_t path[64];
  int depth = 0;
  return b_[descend(top, x, path, depth)];
}

Rgb HierarchicalRadiosity::gathered_at(uint32_t top, Vec3 x) const {
  if (top >= patches_.size()) return Rgb();
  uint32_t path[64];
  int depth = 0;
  descend(top, x, path, depth);
  const Vec3 nx = patches_[top].normal;
  Rgb sum;
  for (int k = 0; k < depth; ++k) {
    const uint32_t n = path[k];
    for (uint32_t l = link_begin_[n]; l < link_begin_[n + 1]; ++l) {
      const Link& link = links_[l];
      if (link.ff_vis <= 0) continue;  // occluded from all of the receiver's points
      if (is_cluster(link.source)) {
        sum += link_source_b(link) * (member_ff(link, x, nx) * link.ff_vis);
        continue;
      }
      float v = 1;
      // Partly occluded: whether p sees the source's centroid (at shadow boundaries the links
      // are refined, so the sources there are small).
      if (link.ff_vis < 1 && visibility_) v = visibility_(x, centroid(link.source));
      if (v > 0) sum += b_[link.source] * (point_to_node_ff(x, nx, link.source) * v);
    }
  }
  // The links of the clusters containing the patch.
  if (!tree_.empty())
    for (uint32_t c = tree_.parent_of(top); c != ClusterTree::kNone; c = tree_.clusters()[c].parent)
      for (uint32_t l = cluster_link_begin_[c]; l < cluster_link_begin_[c + 1]; ++l) {
        const Link& link = cluster_links_[l];
        if (member_visible(link, c, top)) sum += link_source_b(link) * member_ff(link, x, nx);
      }
  return patches_[top].emission + patches_[top].rho * sum;
}

std::vector<HierarchicalLeaf> HierarchicalRadiosity::leaves() const {
  std::vector<HierarchicalLeaf> out;
  std::vector<uint32_t> stack;
  for (uint32_t top = 0; top < patches_.size(); ++top) {
    stack.assign(1, top);
    while (!stack.empty()) {
      const uint32_t n = stack.back();
      stack.pop_back();
      if (nodes_[n].child != kLeaf) {
        for (uint32_t i = 4; i-- > 0;) stack.push_back(nodes_[n].child + i);
        continue;
      }
      HierarchicalLeaf leaf;
      leaf.top = top;
      leaf.corners = static_cast<uint8_t>(corner_points(n, leaf.p));
      leaf.area = nodes_[n].area;
      leaf.b = b_[n];
      out.push_back(leaf);
    }
  }
  return out;
}

}  // namespace penumbra
