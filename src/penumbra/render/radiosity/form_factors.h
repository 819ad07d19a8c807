#pragma once
/// Form factors between the elements of a radiosity mesh: F_ij, the fraction of the energy
/// leaving element i (diffusely) that arrives at element j, as a dense row-major matrix, by the
/// hemicube (Cohen, Greenberg 1985, "The Hemi-Cube: A Radiosity Solution for Complex
/// Environments") or by Monte Carlo ray casting from area to area (Cohen, Wallace 1993,
/// "Radiosity and Realistic Image Synthesis", chapter 4; visibility as in Wallace, Elmquist,
/// Haines 1989, "A Ray Tracing Algorithm for Progressive Radiosity", through the world's
/// acceleration structure).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {

class World;
class RadiosityMesh;

/// How to compute form factors.
struct FormFactorOptions {
  std::string method = "raycast";  ///< "raycast" or "hemicube"
  int resolution = 64;             ///< hemicube: cells across the top face (even; the four side
                                   ///< faces are resolution x resolution / 2)
  int rays = 256;                  ///< raycast: rays per element
  uint64_t seed = 0;               ///< raycast: element i draws from Pcg32(hash(seed, i))
};

/// A dense form-factor matrix with its diagnostics.
struct FormFactors {
  size_t n = 0;          ///< elements
  std::vector<float> f;  ///< n x n, row-major: f[i * n + j] = F_ij
  double seconds = 0;    ///< wall time of the computation (without the diagnostics)
  /// Reciprocity error, energy-weighted: sum over pairs i < j of |A_i F_ij - A_j F_ji| divided by
  /// the sum of (A_i F_ij + A_j F_ji); 0 when A_i F_ij = A_j F_ji exactly. (A per-pair maximum
  /// would be dominated by pairs that exchange a single Monte Carlo ray.)
  double reciprocity_error = 0;
  double max_row_sum = 0, min_row_sum = 0;  ///< extremes of sum_j F_ij (<= 1; = 1 when closed)

  /// F_ij.
  float at(size_t i, size_t j) const { return f[i * n + j]; }
};

/// Form factors of `mesh` (built from `world`) by options.method; throws Error for an unknown
/// method, bad parameters, or a matrix beyond the memory limit (core/memory_limit.h).
FormFactors compute_form_factors(const World& world, const RadiosityMesh& mesh,
                                 const FormFactorOptions& options);

/// Ray-cast form factors: from each element i, `rays` rays from uniform points of i in cosine-
/// distributed directions; the closest hit (the world's true geometry: spheres are spheres) is
/// located on the mesh (side facing i) and adds 1 / rays to F_ij. Unbiased; a row sums to the
/// fraction of rays that hit a meshed surface. Parallel over rows; independent of thread count.
FormFactors raycast_form_factors(const World& world, const RadiosityMesh& mesh, int rays,
                                 uint64_t seed);

/// Hemicube form factors from the mesh alone: a hemicube of `resolution` at each element's
/// centroid, every element facing it clipped and rasterised onto its five faces with a z-buffer
/// (visibility among the mesh's elements), F_ij = the delta form factors of the cells showing j.
/// Each cell's delta form factor is its exact point-to-polygon form factor (Lambert's contour
/// formula), so the cells sum to 1 and a closed scene's rows sum to 1 up to rounding. Cost
/// O(n^2) projections plus the cells they cover.
FormFactors hemicube_form_factors(const RadiosityMesh& mesh, int resolution);

/// Fills the row-sum and reciprocity diagnostics of `ff` for `mesh`'s element areas.
void form_factor_diagnostics(const RadiosityMesh& mesh, FormFactors& ff);

}  // namespace penumbra
