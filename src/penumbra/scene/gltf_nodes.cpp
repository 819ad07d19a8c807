#include "penumbra/scene/gltf_nodes.h"

#include <cmath>

namespace penumbra {

namespace {

std::string node_path(int i) {
  return "/nodes/" + std::to_string(i);
}

void check_length(const GltfSource& src, const std::vector<double>& v, size_t n,
                  const std::string& path) {
  if (!v.empty() && v.size() != n) src.fail(path, "expected " + std::to_string(n) + " numbers");
  for (double x : v)
    if (!std::isfinite(x)) src.fail(path, "numbers must be finite");
}

// The parent of each node (-1 for none), from every node's children list: an index out of range
// or a node listed twice is an error.
std::vector<int> parents(const GltfSource& src) {
  const auto& nodes = src.model.nodes;
  std::vector<int> parent(nodes.size(), -1);
  for (size_t p = 0; p < nodes.size(); ++p) {
    const std::vector<int>& ch = nodes[p].children;
    for (size_t k = 0; k < ch.size(); ++k) {
      const std::string at = node_path(int(p)) + "/children/" + std::to_string(k);
      if (ch[k] < 0 || size_t(ch[k]) >= nodes.size())
        src.fail(at, "node " + std::to_string(ch[k]) + " out of range (" +
                         std::to_string(nodes.size()) + " nodes)");
      if (parent[size_t(ch[k])] != -1)
        src.fail(at, "node " + std::to_string(ch[k]) + " already has parent node " +
                         std::to_string(parent[size_t(ch[k])]) +
                         " (the node graph must be a forest)");
      parent[size_t(ch[k])] = int(p);
    }
  }
  return parent;
}

// With one parent per node, a cycle is a chain of parents that comes back to where it started.
// Each node is walked once: state 1 = on the current chain, 2 = known to reach a root.
void check_cycles(const GltfSource& src, const std::vector<int>& parent) {
  std::vector<char> state(parent.size(), 0);
  for (size_t start = 0; start < parent.size(); ++start) {
    int n = int(start);
    while (n != -1 && state[size_t(n)] == 0) {
      state[size_t(n)] = 1;
      n = parent[size_t(n)];
    }
    if (n != -1 && state[size_t(n)] == 1)
      src.fail(node_path(n), "the node graph has a cycle through this node");
    for (n = int(start); n != -1 && state[size_t(n)] == 1; n = parent[size_t(n)])
      state[size_t(n)] = 2;
  }
}

std::vector<int> scene_roots(const GltfSource& src, const std::vector<int>& parent,
                             std::vector<std::string>& warnings) {
  const tinygltf::Model& m = src.model;
  std::vector<int> roots;
  if (m.scenes.empty()) {
    for (size_t i = 0; i < parent.size(); ++i)
      if (parent[i] == -1) roots.push_back(int(i));
    if (!roots.empty())
      warnings.push_back(src.message("/scenes", "no scenes: rendering every root node"));
    return roots;
  }
  const int s = m.defaultScene < 0 ? 0 : m.defaultScene;
  if (size_t(s) >= m.scenes.size())
    src.fail("/scene", "scene " + std::to_string(s) + " out of range (" +
                           std::to_string(m.scenes.size()) + " scenes)");
  std::vector<char> seen(parent.size(), 0);
  const std::vector<int>& nodes = m.scenes[size_t(s)].nodes;
  for (size_t k = 0; k < nodes.size(); ++k) {
    const std::string at = "/scenes/" + std::to_string(s) + "/nodes/" + std::to_string(k);
    const int n = nodes[k];
    if (n < 0 || size_t(n) >= parent.size())
      src.fail(at, "node " + std::to_string(n) + " out of range (" + std::to_string(parent.size()) +
                       " nodes)");
    if (parent[size_t(n)] != -1)
      src.fail(at, "node " + std::to_string(n) + " is a child of node " +
                       std::to_string(parent[size_t(n)]) + ", not a root");
    if (seen[size_t(n)]) src.fail(at, "node " + std::to_string(n) + " is listed twice");
    seen[size_t(n)] = 1;
    roots.push_back(n);
  }
  return roots;
}

}  // namespace

Mat4 gltf_local_matrix(const GltfSource& src, int index) {
  const tinygltf::Node& n = src.model.nodes[size_t(index)];
  const std::string at = node_path(index);
  check_length(src, n.matrix, 16, at + "/matrix");
  check_length(src, n.translation, 3, at + "/translation");
  check_length(src, n.rotation, 4, at + "/rotation");
  check_length(src, n.scale, 3, at + "/scale");
  Mat4 m = Mat4::identity();
  if (!n.matrix.empty()) {
    // glTF stores matrices column by column; Mat4 is m[row][column].
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m.m[size_t(r)][size_t(c)] = n.matrix[size_t(c * 4 + r)];
    return m;
  }
  // T * R * S with the unit quaternion (x, y, z, w).
  double x = 0, y = 0, z = 0, w = 1;
  if (!n.rotation.empty()) {
    x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
    const double len = std::sqrt(x * x + y * y + z * z + w * w);
    if (!(len > 0)) src.fail(at + "/rotation", "the quaternion must not be zero");
    x /= len, y /= len, z /= len, w /= len;
  }
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                          {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                          {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      m.m[size_t(i)][size_t(j)] = r[i][j] * (n.scale.empty() ? 1.0 : n.scale[size_t(j)]);
    m.m[size_t(i)][3] = n.translation.empty() ? 0.0 : n.translation[size_t(i)];
  }
  return m;
}

std::vector<GltfNodeVisit> traverse_gltf_scene(const GltfSource& src,
                                               std::vector<std::string>& warnings) {
  const std::vector<int> parent = parents(src);
  check_cycles(src, parent);
  const std::vector<int> roots = scene_roots(src, parent, warnings);
  // Depth-first pre-order with an explicit stack (children pushed in reverse).
  std::vector<GltfNodeVisit> out;
  std::vector<GltfNodeVisit> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it)
    stack.push_back({*it, gltf_local_matrix(src, *it), node_path(*it)});
  while (!stack.empty()) {
    GltfNodeVisit v = std::move(stack.back());
    stack.pop_back();
    for (const auto& row : v.world.m)
      for (double x : row)
        if (!std::isfinite(x)) src.fail(v.path, "the world transform overflows (not finite)");
    const std::vector<int>& ch = src.model.nodes[size_t(v.node)].children;
    for (auto it = ch.rbegin(); it != ch.rend(); ++it)
      stack.push_back({*it, v.world * gltf_local_matrix(src, *it), node_path(*it)});
    out.push_back(std::move(v));
  }
  return out;
}

}  // namespace penumbra
