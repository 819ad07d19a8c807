#include "penumbra/render/photon/photon_map.h"

#include <cmath>
#include <numbers>

namespace penumbra {

namespace {

/// Of the search radius, how far from the tangent plane a photon may lie and still belong to
/// the surface (Jensen 2001 flattens the search sphere into a disc for the same reason).
constexpr float kPlaneFraction = 0.125f;

}  // namespace

float PhotonMap::gather(Vec3 p, Vec3 n, const DensityQuery& q, std::vector<KdNeighbor>& out) const {
  const float max_r2 = q.max_radius * q.max_radius;
  const float plane = kPlaneFraction * q.max_radius;
  const size_t k = size_t(q.k);
  tree_.nearest(p, k, max_r2, out, [&](const Photon& ph) {
    return dot(ph.incident(), n) > 0.0f && std::fabs(dot(ph.p - p, n)) <= plane;
  });
  const bool full = out.size() == k;
  if (out.empty()) return 0.0f;
  // With k photons found, the estimate's disc reaches the farthest; with fewer, the whole
  // search radius was empty beyond them.
  return full ? out.back().dist2 : max_r2;
}

Rgb PhotonMap::radiance(const SurfaceInteraction& si, const Material& m, const DensityQuery& q,
                        std::vector<KdNeighbor>& scratch) const {
  const Vec3 n = face_forward(si.ng, si.wo);
  const float r2 = gather(si.p, n, q, scratch);
  if (!(r2 > 0.0f)) return {};
  const Vec3 wo = si.to_local(si.wo);
  Rgb sum;
  for (const KdNeighbor& nb : scratch) {
    const Photon& ph = tree_.points()[nb.index];
    const Rgb f = m.eval(wo, si.to_local(ph.incident()), TransportMode::kRadiance);
    sum += f * ph.power * (1.0f - nb.dist2 / r2);
  }
  return sum * (2.0f * std::numbers::inv_pi_v<float> / r2);
}

Rgb PhotonMap::irradiance(Vec3 p, Vec3 n, const DensityQuery& q,
                          std::vector<KdNeighbor>& scratch) const {
  const float r2 = gather(p, n, q, scratch);
  if (!(r2 > 0.0f)) return {};
  Rgb sum;
  for (const KdNeighbor& nb : scratch)
    sum += tree_.points()[nb.index].power * (1.0f - nb.dist2 / r2);
  return sum * (2.0f * std::numbers::inv_pi_v<float> / r2);
}

}  // namespace penumbra
