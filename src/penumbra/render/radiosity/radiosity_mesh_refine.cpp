// Adaptive subdivision of a radiosity mesh (RadiosityMesh::subdivide): pieces split into four
// where the integrator found the solution changing quickly (Cohen, Wallace 1993, "Radiosity and
// Realistic Image Synthesis", section 8.4: a posteriori refinement by the gradient between
// neighbours).
#include <algorithm>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/render/radiosity/radiosity_mesh.h"

namespace penumbra {

void RadiosityMesh::subdivide(const std::vector<uint32_t>& front_elements) {
  const size_t n = elements_.size();
  std::vector<char> split(n / 2, 0);
  for (const uint32_t f : front_elements) {
    if (f % 2 != 0 || f >= n)
      throw Error(fmt::format("radiosity mesh: cannot split element {} (front elements are the "
                              "even indices below {})",
                              f, n));
    if (split[f / 2]) throw Error(fmt::format("radiosity mesh: element {} split twice", f));
    split[f / 2] = 1;
  }
  if (pieces_.empty()) {  // the tree's roots: the pieces as built
    base_pieces_ = static_cast<uint32_t>(n / 2);
    pieces_.resize(base_pieces_);
    element_piece_.resize(base_pieces_);
    for (uint32_t k = 0; k < base_pieces_; ++k) {
      const RadiosityElement& e = elements_[2 * size_t(k)];
      const Vec3 o = vertices_[e.v[0]];
      pieces_[k] = {o, vertices_[e.v[1]] - o, vertices_[e.v[e.corners - 1]] - o, UINT32_MAX,
                    2 * k, e.corners};
      element_piece_[k] = k;
    }
  }
  const auto midpoint = [&](uint32_t a, uint32_t b) {
    const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
    const auto [it, fresh] = midpoint_.try_emplace(key, static_cast<uint32_t>(vertices_.size()));
    if (fresh) vertices_.push_back((vertices_[a] + vertices_[b]) * 0.5f);  // symmetric in a, b
    return it->second;
  };
  // New leaves' front and back elements, by piece.
  std::unordered_map<uint32_t, std::pair<RadiosityElement, RadiosityElement>> fresh_leaves;
  for (uint32_t k = 0; k < n / 2; ++k) {
    if (!split[k]) continue;
    const RadiosityElement& front = elements_[2 * size_t(k)];
    const RadiosityElement& back = elements_[2 * size_t(k) + 1];
    const uint32_t* v = front.v;
    uint32_t kids[4][4];
    const int corners = front.corners;
    if (corners == 4) {
      const uint32_t m01 = midpoint(v[0], v[1]), m12 = midpoint(v[1], v[2]),
                     m23 = midpoint(v[2], v[3]), m30 = midpoint(v[3], v[0]);
      const uint32_t c = static_cast<uint32_t>(vertices_.size());
      vertices_.push_back((vertices_[v[0]] + vertices_[v[2]]) * 0.5f);
      const uint32_t q[4][4] = {{v[0], m01, c, m30}, {m01, v[1], m12, c}, {m30, c, m23, v[3]},
                                {c, m12, v[2], m23}};
      std::copy(&q[0][0], &q[0][0] + 16, &kids[0][0]);
    } else {
      const uint32_t m01 = midpoint(v[0], v[1]), m12 = midpoint(v[1], v[2]),
                     m02 = midpoint(v[0], v[2]);
      const uint32_t t[4][4] = {
          {v[0], m01, m02, 0}, {m01, v[1], m12, 0}, {m02, m12, v[2], 0}, {m12, m02, m01, 0}};
      std::copy(&t[0][0], &t[0][0] + 16, &kids[0][0]);
    }
    const uint32_t piece = element_piece_[k];
    const auto first = static_cast<uint32_t>(pieces_.size());
    pieces_[piece].child = first;
    for (const auto& kid : kids) {
      RadiosityElement f = front;
      std::copy(kid, kid + 4, f.v);
      const Vec3 o = vertices_[kid[0]], e1 = vertices_[kid[1]] - o,
                 e2 = vertices_[kid[corners - 1]] - o;
      const float len = length(cross(e1, e2));
      f.area = corners == 4 ? len : 0.5f * len;
      f.centroid = corners == 4 ? o + (e1 + e2) * 0.5f : o + (e1 + e2) / 3.0f;
      RadiosityElement b = back;  // the same corners, in the opposite order (as build does)
      std::copy(f.v, f.v + 4, b.v);
      std::swap(b.v[1], b.v[corners - 1]);
      b.area = f.area, b.centroid = f.centroid;
      fresh_leaves.emplace(static_cast<uint32_t>(pieces_.size()), std::make_pair(f, b));
      pieces_.push_back({o, e1, e2, UINT32_MAX, 0, front.corners});
    }
  }
  // Renumber: depth first over the original pieces, children in place of their parent.
  std::vector<RadiosityElement> out;
  out.reserve(n + 6 * front_elements.size());
  element_piece_.clear();
  std::vector<uint32_t> stack;
  for (uint32_t root = base_pieces_; root-- > 0;) stack.push_back(root);
  while (!stack.empty()) {
    const uint32_t p = stack.back();
    stack.pop_back();
    Piece& node = pieces_[p];
    if (node.child != UINT32_MAX) {
      for (uint32_t i = 4; i-- > 0;) stack.push_back(node.child + i);
      continue;
    }
    const auto index = static_cast<uint32_t>(out.size());
    const auto it = fresh_leaves.find(p);
    if (it != fresh_leaves.end()) {
      out.push_back(it->second.first), out.push_back(it->second.second);
    } else {
      out.push_back(elements_[node.element]), out.push_back(elements_[node.element + 1]);
    }
    out[index].twin = index + 1, out[index + 1].twin = index;
    node.element = index;
    element_piece_.push_back(p);
  }
  elements_ = std::move(out);
  refinements_.push_back(front_elements);
}

}  // namespace penumbra
