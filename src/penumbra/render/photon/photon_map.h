#pragma once
/// A photon map: photons in a balanced kd-tree, and the density estimates that turn them into
/// radiance and irradiance (Jensen 1996, "Global Illumination using Photon Maps"; Jensen 2001,
/// "Realistic Image Synthesis Using Photon Mapping").
#include <cstdint>
#include <vector>

#include "penumbra/accel/point_kdtree.h"
#include "penumbra/core/color.h"
#include "penumbra/render/material/material.h"
#include "penumbra/render/photon/photon.h"
#include "penumbra/render/surface_interaction.h"

namespace penumbra {

/// How a density estimate gathers photons.
struct DensityQuery {
  int k = 50;            ///< photons per estimate (the k nearest)
  float max_radius = 0;  ///< farthest photon used (world units)
};

/// The photons of one map, searchable by position. Photons count only where they belong to the
/// surface being estimated: their incident direction must lie above it (on the side the query
/// looks from) and they must lie near its tangent plane, so that light on the far side of a thin
/// wall and on a wall meeting the surface at a corner does not leak in.
class PhotonMap {
 public:
  PhotonMap() = default;
  explicit PhotonMap(std::vector<Photon> photons) : tree_(std::move(photons)) {}

  size_t size() const { return tree_.size(); }
  bool empty() const { return tree_.empty(); }
  size_t bytes() const { return tree_.bytes(); }
  const PointKdTree<Photon>& tree() const { return tree_; }

  /// Outgoing radiance towards si.wo from the photons near si, through the BSDF `m` (resolved
  /// at si): sum_p f(wo, wi_p) Phi_p K(d_p / r) / r^2, with the Epanechnikov kernel
  /// K(t) = 2 (1 - t^2) / pi, a consistent kernel (Garcia et al. 2014, "Kernel Estimation
  /// Applied to Photon Mapping"). `scratch` is reused between calls.
  Rgb radiance(const SurfaceInteraction& si, const Material& m, const DensityQuery& q,
               std::vector<KdNeighbor>& scratch) const;
  /// Irradiance at p on the side of the unit normal n, with the same kernel.
  Rgb irradiance(Vec3 p, Vec3 n, const DensityQuery& q, std::vector<KdNeighbor>& scratch) const;

 private:
  /// The k nearest photons that belong to the surface at p with side normal n; returns the
  /// squared radius of the estimate (0 when none).
  float gather(Vec3 p, Vec3 n, const DensityQuery& q, std::vector<KdNeighbor>& out) const;

  PointKdTree<Photon> tree_;
};

}  // namespace penumbra
