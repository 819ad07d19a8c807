#pragma once
/// The ray-box test of the binary BVH: per-ray values computed once and the slab test of a node.
#include "penumbra/accel/build/bvh_node.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/geometry/prepared_ray.h"

namespace penumbra {

/// Per-ray values of the slab test (Williams et al. 2005, "An Efficient and Robust Ray-Box
/// Intersection Algorithm": near and far planes chosen once per ray from the direction signs).
struct BvhRay {
  float o[3];        ///< origin
  float inv[3];      ///< 1 / d (+-inf for a zero component)
  float inv_far[3];  ///< 1 / d scaled by 1 + 2 gamma(3), for conservative exit distances
  int near[3];       ///< index of each axis' near plane in BvhNode::box
  int far[3];        ///< index of each axis' far plane

  explicit BvhRay(const PreparedRay& pr) {
    // Robust exit distances (Pharr, Jakob, Humphreys, "Physically Based Rendering", 3rd ed.,
    // section 3.9.2): scaling 1/d up by 1 + 2 gamma(3) covers the rounding of the subtraction,
    // the division and the products, so a grazing ray never misses a box it touches.
    constexpr float kFarScale = 1.0f + 2.0f * gamma(3);
    for (int a = 0; a < 3; ++a) {
      o[a] = pr.ray.o[a];
      inv[a] = pr.inv_dir[a];
      inv_far[a] = pr.inv_dir[a] * kFarScale;
      near[a] = 2 * a + pr.neg[a];
      far[a] = 2 * a + 1 - pr.neg[a];
    }
  }
};

/// Slab test of one node against [t0, t1]; on a hit returns true and sets `entry`. With a zero
/// direction component and the origin on a plane of that axis, (plane - o) * inv is 0 * inf =
/// NaN; every comparison with NaN is false, so such a term keeps the running bound and the box is
/// not rejected on that axis (the ray lies in the closed slab).
inline bool hit_node(const BvhNode& n, const BvhRay& r, float t0, float t1, float& entry) {
  const float nx = (n.box[r.near[0]] - r.o[0]) * r.inv[0];
  const float ny = (n.box[r.near[1]] - r.o[1]) * r.inv[1];
  const float nz = (n.box[r.near[2]] - r.o[2]) * r.inv[2];
  const float fx = (n.box[r.far[0]] - r.o[0]) * r.inv_far[0];
  const float fy = (n.box[r.far[1]] - r.o[1]) * r.inv_far[1];
  const float fz = (n.box[r.far[2]] - r.o[2]) * r.inv_far[2];
  t0 = nx > t0 ? nx : t0;
  t0 = ny > t0 ? ny : t0;
  t0 = nz > t0 ? nz : t0;
  t1 = fx < t1 ? fx : t1;
  t1 = fy < t1 ? fy : t1;
  t1 = fz < t1 ? fz : t1;
  entry = t0;
  return t0 <= t1;
}

}  // namespace penumbra
