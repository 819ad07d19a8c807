#include "penumbra/accel/collision/collision_mesh.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/collision/triangle_triangle.h"
#include "penumbra/core/dvec3.h"
#include "penumbra/core/error.h"
#include "penumbra/core/timer.h"

namespace penumbra::collision {

namespace {

/// The affine image of p under m (the projective row is ignored: poses are affine).
DVec3 apply(const Mat4& m, const DVec3& p) {
  const auto& a = m.m;
  return {a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3],
          a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3],
          a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3]};
}

}  // namespace

Bounds3 round_outward(const DVec3& lo, const DVec3& hi) {
  Bounds3 b;
  b.lo = {round_down(lo.x), round_down(lo.y), round_down(lo.z)};
  b.hi = {round_up(hi.x), round_up(hi.y), round_up(hi.z)};
  return b;
}

CollisionMesh::CollisionMesh(const TriangleMesh& mesh, const Transform& pose) {
  const size_t n = mesh.triangle_count();
  if (n > std::numeric_limits<uint32_t>::max() / 4)
    throw Error(fmt::format("collision mesh: {} triangles is too many", n));
  local_.resize(3 * n);
  for (size_t i = 0; i < 3 * n; ++i) {
    const uint32_t v = mesh.indices[i];
    if (v >= mesh.positions.size())
      throw Error(fmt::format("collision mesh: triangle {} uses vertex {} of {}", i / 3, v,
                              mesh.positions.size()));
    local_[i] = mesh.positions[v];
  }

  // References to every triangle with finite local coordinates, as the BVH builder wants them.
  const Timer timer;
  PrimRefs refs;
  refs.refs.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 &a = local_[3 * i], &b = local_[3 * i + 1], &c = local_[3 * i + 2];
    if (!is_finite(a) || !is_finite(b) || !is_finite(c)) continue;
    // x + 0 turns -0 into +0, so min/max never depend on the order of combination.
    const Vec3 lo = min(a, min(b, c)) + Vec3(0.0f), hi = max(a, max(b, c)) + Vec3(0.0f);
    refs.refs.push_back({lo, static_cast<uint32_t>(i), hi, 0});
    refs.bounds.extend(Bounds3(lo, hi));
    refs.centroid_bounds.extend(lo + hi);
  }
  BvhBuildParams params;
  params.max_leaf = kMaxLeaf;
  BinaryBvh bvh = build_binary_bvh(std::move(refs), params);
  stats_.nodes = bvh.node_count();
  nodes_ = std::move(bvh.nodes);
  leaf_ids_.reserve(bvh.refs.size());
  for (const PrimRef& r : bvh.refs) leaf_ids_.push_back(r.id);
  stats_.leaves = bvh.leaves;
  stats_.max_depth = bvh.max_depth;
  stats_.build_ms = timer.elapsed_ms();
  stats_.bytes = nodes_.size() * sizeof(BvhNode) + leaf_ids_.size() * sizeof(uint32_t) +
                 n * (sizeof(DTriangle) + sizeof(Bounds3) + 1);
  set_pose(pose);
}

void CollisionMesh::set_pose(const Transform& pose) {
  const Timer timer;
  const size_t n = local_.size() / 3;
  world_.resize(n);
  boxes_.resize(n);
  valid_.resize(n);
  valid_count_ = 0;
  const Mat4& m = pose.matrix();
  for (size_t i = 0; i < n; ++i) {
    DTriangle& t = world_[i];
    for (int k = 0; k < 3; ++k) t[k] = apply(m, DVec3(local_[3 * i + k]));
    valid_[i] = is_valid_triangle(t) ? 1 : 0;
    valid_count_ += valid_[i];
    boxes_[i] = valid_[i] ? round_outward(min(t[0], min(t[1], t[2])), max(t[0], max(t[1], t[2])))
                          : Bounds3();
  }
  // Refit: children follow their parent in the array, so a reverse sweep sees them first.
  // Invalid triangles contribute nothing (a leaf of only those gets an empty box).
  for (size_t k = nodes_.size(); k-- > 0;) {
    if (k == 1) continue;  // padding slot
    BvhNode& node = nodes_[k];
    Bounds3 box;
    if (node.is_leaf()) {
      for (uint32_t j = node.index; j < node.index + node.count; ++j)
        box.extend(boxes_[leaf_ids_[j]]);
    } else {
      box = join(nodes_[node.index].bounds(), nodes_[node.index + 1].bounds());
    }
    node.set_bounds(box);
  }
  stats_.pose_ms = timer.elapsed_ms();
}

}  // namespace penumbra::collision
