#pragma once
/// Solvers of the radiosity system B_i = E_i + rho_i sum_j F_ij B_j (per colour channel) with a
/// dense form-factor matrix: Jacobi, Gauss-Seidel and progressive refinement (Cohen, Chen,
/// Wallace, Greenberg 1988, "A Progressive Refinement Approach to Fast Radiosity Image
/// Generation"), selectable by name.
#include <cstddef>
#include <string>
#include <vector>

#include "penumbra/core/color.h"

namespace penumbra {

/// A radiosity system of n elements: emission, reflectance, area and the form factors.
struct RadiositySystem {
  size_t n = 0;
  const float* f = nullptr;   ///< n x n row-major, f[i * n + j] = F_ij: the fraction of the energy
                              ///< leaving i that arrives at j (so element i gathers with row i)
  std::vector<Rgb> rho;       ///< diffuse reflectance per element, each channel in [0, 1)
  std::vector<Rgb> emission;  ///< emitted radiosity per element
  std::vector<float> area;    ///< element areas (progressive refinement only: shooter choice
                              ///< and the ambient term)
};

/// How to solve: the method's name, the tolerance on the relative residual, an iteration cap.
struct SolveOptions {
  std::string method = "gauss-seidel";  ///< one of radiosity_solver_names()
  double tolerance = 1e-4;              ///< stop when radiosity_residual() <= tolerance
  int max_iterations = 1000;            ///< stop after this many iterations, converged or not
  size_t shots_per_iteration = 0;       ///< progressive: shots per iteration (0 = n, one sweep's
                                        ///< worth of work)
};

/// The solution and how it was reached.
struct SolveResult {
  std::vector<Rgb> b;             ///< radiosity per element
  std::vector<double> residuals;  ///< residuals[k]: relative residual after k iterations
                                  ///< (residuals[0] is that of the initial guess B = E)
  int iterations = 0;             ///< iterations done (residuals.size() - 1)
  double seconds = 0;             ///< wall time of the solve
  bool converged = false;         ///< the last residual is <= the tolerance
  std::vector<Rgb> ambient;       ///< progressive only: per-element display correction
                                  ///< rho_i * ambient (display b + ambient); empty otherwise
};

/// Names accepted by SolveOptions::method: "jacobi", "gauss-seidel", "progressive".
const std::vector<std::string>& radiosity_solver_names();

/// Relative residual of b: max_i lum(|E_i + rho_i sum_j F_ij b_j - b_i|) / max_i lum(E_i), with
/// lum() the Rec. 709 luminance of the per-channel absolute values (absolute when E = 0).
/// Bounds the error: max |b - B*| <= residual * max lum(E) / (1 - max_i rho_i sum_j F_ij).
double radiosity_residual(const RadiositySystem& system, const std::vector<Rgb>& b);

/// Solves `system` with `options.method`; throws Error for an unknown name (listing the valid
/// ones) or inconsistent sizes.
SolveResult solve_radiosity(const RadiositySystem& system, const SolveOptions& options);

}  // namespace penumbra
