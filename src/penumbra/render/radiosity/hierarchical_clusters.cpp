// Clustering for hierarchical radiosity: the cluster tree above the top-level patches, the
// cluster oracle, the links with a cluster at one end or both, and gathering through them.
//
// The model (after Smits, Arvo, Greenberg 1994, "A Clustering Algorithm for Radiosity in Complex
// Environments"; the cluster as a point source of its projected area is that of Sillion 1995,
// "A Unified Hierarchical Algorithm for Global Illumination with Scattering Volumes and Object
// Clusters", made directional):
// - Sending. A cluster sends as a point at its area-weighted centre with its projected area
//   toward the receiver, P = sum over its member patches of A max(0, n . w), summed exactly
//   when the link is made. The radiosity it sends is its members' exitance as the receiver
//   sees it: the mean B over link_grid^2 members drawn by projected area (so an unbiased
//   estimate of sum B A max(0, n . w) / P), counting only the members exposed toward the
//   receiver (a ray toward it leaves the cluster's bounding sphere). A uniform cluster sends
//   exactly its B; the dark inside of a closed object, whose faces face every receiver across
//   the object, sends nothing.
// - Receiving (Smits et al.). Every top-level patch p below a receiving cluster gathers
//   rho_p B_s F_p V_p with F_p = max(0, n_p . w) P / (pi d^2) from its own centroid and normal
//   to the source's centre (a node source: A max(0, -n_s . w) in place of P), and V_p one ray
//   from p's centroid to a point of the source, kept as a bit per member. Energy goes only to
//   the members that face and see the source, each by its own orientation. The cost per link
//   is the receiver's size, sum over links of |R| about (links per cluster) k log k.
// - The oracle bounds what a link can carry to any point of its receiver:
//   rho_max(R) min(B_max(S), sum_S lum(B) A cos / (pi d^2)), sums and maxima over the members
//   of each side that can face the other (a corner of the other's box in front of its plane;
//   cos bounded over the cone of directions between the bounding spheres), d the distance
//   between the two boxes. A link is made only when this is below the threshold (epsilon
//   times the mean radiosity, as for patches) and its form factor bound P / (pi d^2) below
//   kMaxClusterFormFactor (so that a point source is a fair model of the cluster even while
//   it is dark; boxes that touch never qualify), else the side with the larger bounding
//   sphere is split; pairs of nodes go to the patch oracle. A cluster link thus carries less
//   than the threshold of Hanrahan et al., and its point approximations err by less than that.
// - Push-pull. The members' gathered radiosity joins their quadtrees' (push); a cluster holds
//   no radiosity of its own, its sources read their members' current B (pull). In a closed
//   scene of uniform E and rho every link then sends B exactly, and the solution is
//   E / (1 - rho) up to the form factors' error.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/render/radiosity/hierarchical_radiosity.h"

namespace penumbra {

namespace {

constexpr uint8_t kReceives = 1, kSends = 2;
constexpr uint32_t kExposed = 1u << 31;  // in a link's source sample: see source_samples
constexpr float kInvPi = std::numbers::inv_pi_v<float>;
// The largest bound P / (pi d^2) of a cluster link's form factor (P the facing members'
// projected area bound, d the distance between the boxes): for a flat cluster P is about
// pi r^2, so (r / d)^2 <= 0.1, and the point source it is taken for is within about 10 % of
// it.
constexpr double kMaxClusterFormFactor = 0.1;

// Form factor from a differential area at x (normal nx) to a point source of projected area
// `pa` at c: cos_x pa / (pi d^2), at most 1.
float point_to_cluster_ff(Vec3 x, Vec3 nx, Vec3 c, float pa) {
  const Vec3 d = c - x;
  const float r2 = dot(d, d);
  if (r2 <= 0) return 0;
  const float cos_x = dot(nx, d) / std::sqrt(r2);
  if (cos_x <= 0) return 0;
  return std::min(1.f, cos_x * pa * kInvPi / r2);
}

// Distance between two boxes (0 where they touch or overlap).
float box_distance(const Bounds3& a, const Bounds3& b) {
  float d2 = 0;
  for (int i = 0; i < 3; ++i) {
    const float g = std::max(0.f, std::max(a.lo[i] - b.hi[i], b.lo[i] - a.hi[i]));
    d2 += g * g;
  }
  return std::sqrt(d2);
}

}  // namespace

// The tree over the top-level patches' boxes, and per cluster what its members share.
void HierarchicalRadiosity::build_clusters() {
  std::vector<ClusterInput> in(patches_.size());
  for (uint32_t t = 0; t < patches_.size(); ++t) {
    Vec3 c[4];
    const int k = corner_points(t, c);
    for (int i = 0; i < k; ++i) in[t].box.extend(c[i]);
    in[t].centroid = centroid(t);
    in[t].area = nodes_[t].area;
  }
  tree_ = ClusterTree::build(in);
  const size_t n = tree_.clusters().size();
  cluster_flags_.assign(n, 0);
  for (size_t c = n; c-- > 0;)
    for (uint32_t ref : tree_.clusters()[c].child)
      cluster_flags_[c] |= is_cluster(ref)
                               ? cluster_flags_[ref & ~ClusterTree::kClusterBit]
                               : (receives(ref) ? kReceives : 0) | (sends(ref) ? kSends : 0);
}

HierarchicalRadiosity::Extent HierarchicalRadiosity::extent(uint32_t ref) const {
  Extent e;
  if (is_cluster(ref)) {
    const ClusterTree::Cluster& c = cluster(ref);
    e.box = c.box;
    e.centre = c.centre;
  } else {
    Vec3 c[4];
    const int k = corner_points(ref, c);
    for (int i = 0; i < k; ++i) e.box.extend(c[i]);
    e.centre = centroid(ref);
  }
  e.radius = length(max(e.box.hi - e.centre, e.centre - e.box.lo));
  return e;
}

// What one side of a pair can send to or receive from the box `other` of the other side. A
// member counts when some corner of that box lies strictly in front of its plane; where the
// two bounding spheres are apart, the directions between them lie within angle beta (cos_b,
// sin_b) of the unit `dir` (pointing away from this side), and a member whose normal is at angle
// theta from dir has then a cosine of at most cos(max(0, theta - beta)) toward the other side
// (1 where the spheres overlap: cos_b = -1).
HierarchicalRadiosity::SideBound HierarchicalRadiosity::side_bound(uint32_t ref, Vec3 dir,
                                                                   float cos_b, float sin_b,
                                                                   const Bounds3& other) const {
  SideBound out;
  const Vec3 centre = other.center(), half = other.diagonal() * 0.5f;
  const auto add = [&](uint32_t node, uint32_t top) {
    const Node& d = nodes_[node];
    const Vec3 n = patches_[top].normal;
    // The box's farthest point in front of the plane: its centre plus its support along n.
    const float support = dot(n, centre - d.o) + std::fabs(n.x) * half.x + std::fabs(n.y) * half.y +
                          std::fabs(n.z) * half.z;
    if (support <= 1e-5f * std::sqrt(d.area)) return;
    float cmax = 1;
    if (cos_b > -1) {
      const float c = dot(n, dir);
      if (c < cos_b) cmax = c * cos_b + std::sqrt(std::max(0.f, 1 - c * c)) * sin_b;
      if (cmax <= 0) return;
    }
    const float b = b_[node].luminance();
    out.facing = true;
    out.flux += double(b) * d.area * cmax;
    out.area += double(d.area) * cmax;
    out.b_max = std::max(out.b_max, b);
    out.rho_max = std::max(out.rho_max, patches_[top].rho.max_channel());
  };
  if (!is_cluster(ref)) {
    add(ref, nodes_[ref].top);
    return out;
  }
  const ClusterTree::Cluster& c = cluster(ref);
  const uint32_t* m = tree_.members().data() + c.first;
  for (uint32_t i = 0; i < c.count; ++i) add(m[i], m[i]);
  return out;
}

bool HierarchicalRadiosity::receives(uint32_t ref) const {
  if (is_cluster(ref)) return (cluster_flags_[ref & ~ClusterTree::kClusterBit] & kReceives) != 0;
  return !patches_[nodes_[ref].top].rho.is_black();
}

bool HierarchicalRadiosity::sends(uint32_t ref) const {
  if (is_cluster(ref)) return (cluster_flags_[ref & ~ClusterTree::kClusterBit] & kSends) != 0;
  const Patch& p = patches_[nodes_[ref].top];
  return !p.rho.is_black() || !p.emission.is_black();
}

// The cluster oracle for r <- s (see the top of this file).
HierarchicalRadiosity::ClusterEstimate HierarchicalRadiosity::estimate_cluster(uint32_t r,
                                                                               uint32_t s) const {
  ClusterEstimate e;
  const Extent er = extent(r), es = extent(s);
  e.radius_r = er.radius, e.radius_s = es.radius;
  // Directions from s to r: within the cone of the two bounding spheres around the centres.
  const Vec3 d = er.centre - es.centre;
  const float dist = length(d);
  Vec3 dir(0, 0, 1);
  float cos_b = -1, sin_b = 0;  // all directions
  if (dist > er.radius + es.radius) {
    dir = d / dist;
    sin_b = (er.radius + es.radius) / dist;
    cos_b = std::sqrt(1 - sin_b * sin_b);
  }
  const SideBound src = side_bound(s, dir, cos_b, sin_b, er.box);
  if (!src.facing) return e;
  const SideBound rcv = side_bound(r, -dir, cos_b, sin_b, es.box);
  if (!rcv.facing) return e;
  e.interacts = true;
  // The radiosity s can send to a point of r: at most its brightest facing member's (a form
  // factor is at most 1), and at most its facing flux over pi d^2 for d the boxes' distance.
  const float gap = box_distance(er.box, es.box);
  double b = src.b_max;
  if (gap > 0) b = std::min(b, src.flux / (std::numbers::pi * double(gap) * gap));
  e.transport = rcv.rho_max * b;
  e.form_factor = gap > 0 ? src.area / (std::numbers::pi * double(gap) * gap)
                          : std::numeric_limits<double>::infinity();
  return e;
}

// A cluster link is made when it carries less than the threshold and its form factor is at
// most kMaxClusterFormFactor whatever the radiosity: before the first solve everything but the
// lights is dark, and dark pairs of touching clusters, linked as points, gave some receivers
// form factors summing past 1 / rho (the first solve diverged on the Cornell box with every
// patch clustered).
bool HierarchicalRadiosity::admissible(const ClusterEstimate& e) const {
  return e.transport <= eps_abs_ && e.form_factor <= kMaxClusterFormFactor;
}

// A cluster's self-link becomes the links among its children (Smits et al. 1994).
void HierarchicalRadiosity::link_self(uint32_t cluster_ref, NewLinks& out) {
  const uint32_t a = cluster(cluster_ref).child[0], b = cluster(cluster_ref).child[1];
  if (is_cluster(a)) link_self(a, out);
  if (is_cluster(b)) link_self(b, out);
  link_refs(a, b, out);
  link_refs(b, a, out);
}

// Refine(r, s) with a cluster at one end or both: link where the cluster oracle accepts, else
// split the side with the larger bounding sphere (a cluster into its two children, a node into
// its four) and recurse; two nodes go to the patch oracle (refine).
void HierarchicalRadiosity::link_refs(uint32_t r, uint32_t s, NewLinks& out) {
  if (!receives(r) || !sends(s)) return;
  if (!is_cluster(r) && !is_cluster(s)) {
    if (nodes_[r].top != nodes_[s].top) refine(r, s, out.nodes);
    return;
  }
  const ClusterEstimate e = estimate_cluster(r, s);
  if (!e.interacts) return;
  if (admissible(e)) {
    add_link(is_cluster(r) ? out.clusters : out.nodes, {r, s, -1.f, 0.f});
    return;
  }
  const bool can_r = is_cluster(r) || splittable(r), can_s = is_cluster(s) || splittable(s);
  bool split_s = e.radius_s >= e.radius_r;
  if (!can_r) split_s = true;
  if (!can_s) split_s = false;
  const uint32_t side = split_s ? s : r;
  uint32_t kids[4];
  int count = 0;
  if (is_cluster(side)) {
    kids[0] = cluster(side).child[0], kids[1] = cluster(side).child[1], count = 2;
  } else {
    split(side);
    for (uint32_t i = 0; i < 4; ++i) kids[i] = nodes_[side].child + i;
    count = 4;
  }
  for (int i = 0; i < count; ++i) {
    if (split_s)
      link_refs(r, kids[i], out);
    else
      link_refs(kids[i], s, out);
  }
}

// Up to `count` members of cluster `ref`, stratified by their projected area toward `dir`
// (member k where the running sum of A max(0, n . dir) passes (k + 1/2) / count of it), and that
// projected area in all. Returns the number of members (0 when none faces dir).
int HierarchicalRadiosity::cluster_samples(uint32_t ref, Vec3 dir, int count, uint32_t* out,
                                           float& projected) const {
  const ClusterTree::Cluster& c = cluster(ref);
  const uint32_t* m = tree_.members().data() + c.first;
  const auto weight = [&](uint32_t p) {
    return double(nodes_[p].area) * std::max(0.f, dot(patches_[p].normal, dir));
  };
  double total = 0;
  for (uint32_t i = 0; i < c.count; ++i) total += weight(m[i]);
  projected = static_cast<float>(total);
  if (total <= 0) return 0;
  double sum = 0;
  int k = 0;
  uint32_t last = m[0];
  for (uint32_t i = 0; i < c.count && k < count; ++i) {
    const double w = weight(m[i]);
    if (w <= 0) continue;
    sum += w, last = m[i];
    while (k < count && (k + 0.5) * total / count <= sum) out[k++] = m[i];
  }
  while (k < count) out[k++] = last;  // rounding at the end of the sum
  return count;
}

// The source side of a link from cluster s toward the unit direction `dir` of a receiver whose
// centre is `dist` from s's: `count` sample members (cluster_samples) into words[0, count), each
// marked kExposed when a ray from its centroid toward the receiver leaves s's bounding sphere
// unoccluded (so that a closed object's inside faces, which face every receiver across the
// object, do not count as sending); the exposed centroids go to `exposed`, for the rays from
// the receiver. Returns how many are exposed (-1 when nothing of s faces dir).
int HierarchicalRadiosity::source_samples(uint32_t s, Vec3 dir, float dist, int count,
                                          uint32_t* words, Vec3* exposed, float& projected,
                                          const Visibility& vis) const {
  if (cluster_samples(s, dir, count, words, projected) == 0) return -1;
  const float reach = std::min(2 * extent(s).radius, 0.5f * dist);
  int n = 0;
  for (int k = 0; k < count; ++k) {
    const Vec3 y = centroid(words[k]);
    if (vis && vis(y, y + dir * reach) < 0.5f) continue;
    words[k] |= kExposed;
    exposed[n++] = y;
  }
  return n;
}

// Words of link_data_ that a link needs (see there).
size_t HierarchicalRadiosity::link_words(const Link& l) const {
  size_t words = 0;
  if (is_cluster(l.source)) words += size_t(std::max(1, opt_.link_grid * opt_.link_grid));
  if (is_cluster(l.receiver)) words += (size_t(cluster(l.receiver).count) + 31) / 32;
  return words;
}

// Room in link_data_ for links [first, end), before they are evaluated in parallel.
void HierarchicalRadiosity::allocate_link_data(std::vector<Link>& links, size_t first) {
  for (size_t i = first; i < links.size(); ++i) {
    const size_t words = link_words(links[i]);
    if (link_data_.size() + words > UINT32_MAX)
      throw Error("hierarchical radiosity: more than 2^32 words of cluster link data");
    links[i].data = static_cast<uint32_t>(link_data_.size());
    link_data_.resize(link_data_.size() + words, 0u);
  }
}

// A node receiver <- cluster source link: the mean over the receiver's m x m points x of
// V(x) cos_x P / (pi d^2), V one ray from x to an exposed sample of the source.
void HierarchicalRadiosity::evaluate_from_cluster(Link& l, const std::vector<float>& st, int count,
                                                  const Visibility& vis) {
  const Node& p = nodes_[l.receiver];
  const Vec3 np = patches_[p.top].normal;
  const Vec3 cs = cluster(l.source).centre;
  const Vec3 d = centroid(l.receiver) - cs;
  const float len = length(d);
  std::vector<Vec3> ys(static_cast<size_t>(count));
  uint32_t* words = link_data_.data() + l.data;
  // Nothing of the source may face the receiver's centroid (exposed < 0): the link then
  // carries nothing, but stays, so that re-refinement can split it.
  const int exposed =
      len > 0 ? source_samples(l.source, d / len, len, count, words, ys.data(), l.pa, vis) : -1;
  if (exposed < 0) l.pa = 0;
  double ff = 0, seen = 0, open = 0;
  for (int s = 0; s < count; ++s) {
    const Vec3 x = p.o + p.e1 * st[2 * s] + p.e2 * st[2 * s + 1];
    float v = 0;
    if (exposed > 0) v = vis ? vis(x, ys[size_t((count - 1 - s) % exposed)]) : 1.f;
    const double f = point_to_cluster_ff(x, np, cs, l.pa);
    ff += f * v, open += f, seen += v;
  }
  l.ff = static_cast<float>(ff / double(count));
  l.vis = static_cast<float>(seen / double(count));
  l.ff_vis = open > 0 ? static_cast<float>(ff / open) : l.vis;
}

// Cluster receiver links: the source's samples and projected area, and for each member of the
// receiver that faces the source one ray to a point of it (an exposed sample of a cluster, a
// rule point of a node), kept as a bit; the form factors are per member, in gather_clusters.
// Parallel over links, deterministic.
void HierarchicalRadiosity::evaluate_cluster_links(std::vector<Link>& links, size_t first,
                                                   const Visibility& vis) {
  allocate_link_data(links, first);
  const int m = std::max(1, opt_.link_grid);
  const int count = m * m;
  std::vector<float> st_tri, st_quad;
  rule_points(3, m, st_tri);
  rule_points(4, m, st_quad);
  std::vector<uint32_t> rays(links.size() - first, 0);
  parallel_for(
      links.size() - first,
      [&](size_t k) {
        Link& l = links[first + k];
        const ClusterTree::Cluster& r = cluster(l.receiver);
        const Vec3 cs = is_cluster(l.source) ? cluster(l.source).centre : centroid(l.source);
        const Vec3 d = r.centre - cs;
        const float len = length(d);
        std::vector<Vec3> ys(static_cast<size_t>(count));
        uint32_t* words = link_data_.data() + l.data;
        int exposed = count;
        if (len <= 0) {
          exposed = -1;
        } else if (is_cluster(l.source)) {
          exposed = source_samples(l.source, d / len, len, count, words, ys.data(), l.pa, vis);
          words += count;
          if (vis) rays[k] += uint32_t(count);
        } else {
          const Node& q = nodes_[l.source];
          const std::vector<float>& sq = patches_[q.top].corners == 4 ? st_quad : st_tri;
          for (int s = 0; s < count; ++s)
            ys[size_t(s)] = q.o + q.e1 * sq[2 * s] + q.e2 * sq[2 * s + 1];
        }
        // No member of one side facing the other's centre: no rays, and the link carries
        // nothing (it stays for re-refinement).
        if (exposed < 0) exposed = 0;
        const uint32_t* members = tree_.members().data() + r.first;
        uint32_t facing = 0, seen = 0;
        for (uint32_t i = 0; i < r.count; ++i) {
          const Vec3 x = centroid(members[i]);
          if (dot(patches_[members[i]].normal, cs - x) <= 0) continue;
          ++facing;
          if (exposed == 0) continue;
          if (vis) ++rays[k];
          if (vis && vis(x, ys[i % uint32_t(exposed)]) < 0.5f) continue;
          words[i / 32] |= 1u << (i % 32);
          ++seen;
        }
        l.vis = l.ff_vis = facing > 0 ? float(seen) / float(facing) : 0.f;
        l.ff = 0;  // per member, see member_ff
      },
      16);
  for (uint32_t r : rays) stats_.visibility_rays += r;
}

// The radiosity a cluster source sends along link l: the mean over its samples (drawn by
// projected area toward the receiver, so an unbiased estimate of sum B A max(0, n . w) / P) of
// B of the exposed ones. Exact for a cluster of uniform B that its receiver sees whole; a lit
// outside is not averaged with a dark inside, nor a member with one facing away.
Rgb HierarchicalRadiosity::link_source_b(const Link& l) const {
  if (!is_cluster(l.source)) return b_[l.source];
  const int count = std::max(1, opt_.link_grid * opt_.link_grid);
  const uint32_t* w = link_data_.data() + l.data;
  Rgb sum;
  for (int k = 0; k < count; ++k)
    if (w[k] & kExposed) sum += b_[w[k] & ~kExposed];
  return sum / float(count);
}

// The unoccluded form factor of link l from the point x (normal nx): a point source of the
// link's projected area at a cluster source's centre, or a node source taken as a differential
// area at its centroid.
float HierarchicalRadiosity::member_ff(const Link& l, Vec3 x, Vec3 nx) const {
  if (is_cluster(l.source)) return point_to_cluster_ff(x, nx, cluster(l.source).centre, l.pa);
  const Node& q = nodes_[l.source];
  const Vec3 d = centroid(l.source) - x;
  const float r2 = dot(d, d);
  if (r2 <= 0) return 0;
  const float r = std::sqrt(r2);
  const float cos_x = dot(nx, d) / r, cos_q = -dot(patches_[q.top].normal, d) / r;
  if (cos_x <= 0 || cos_q <= 0) return 0;
  return std::min(1.f, cos_x * cos_q * q.area * kInvPi / r2);
}

// Whether member `patch` of the receiver cluster `cluster_index` of link l sees its source.
bool HierarchicalRadiosity::member_visible(const Link& l, uint32_t cluster_index,
                                           uint32_t patch) const {
  const uint32_t i = tree_.position(patch) - tree_.clusters()[cluster_index].first;
  const uint32_t* bits = link_data_.data() + l.data +
                         (is_cluster(l.source) ? std::max(1, opt_.link_grid * opt_.link_grid) : 0);
  return (bits[i / 32] >> (i % 32)) & 1u;
}

// Gather through the clusters: each top-level patch adds rho times the sum, over the links of
// every cluster above it that it sees the source of, of the source's B toward that cluster times
// the member form factor from its centroid. Parallel over patches, each sum in a fixed order.
void HierarchicalRadiosity::gather_clusters() {
  if (tree_.empty()) return;
  parallel_for(
      cluster_links_.size(),
      [&](size_t l) {
        const Link& link = cluster_links_[l];
        cluster_link_b_[l] = link_source_b(link);
      },
      256);
  parallel_for(
      patches_.size(),
      [&](size_t t) {
        const uint32_t p = uint32_t(t);
        const Vec3 x = centroid(p), nx = patches_[t].normal;
        Rgb sum;
        for (uint32_t c = tree_.parent_of(p); c != ClusterTree::kNone;
             c = tree_.clusters()[c].parent)
          for (uint32_t l = cluster_link_begin_[c]; l < cluster_link_begin_[c + 1]; ++l)
            if (member_visible(cluster_links_[l], c, p))
              sum += cluster_link_b_[l] * member_ff(cluster_links_[l], x, nx);
        gather_[t] += patches_[t].rho * sum;
      },
      64);
}

}  // namespace penumbra
