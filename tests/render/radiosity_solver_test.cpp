#include "penumbra/render/radiosity/radiosity_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"

namespace penumbra {
namespace {

// A system that owns its matrix.
struct OwnedSystem {
  std::vector<float> f;
  RadiositySystem sys;
  void finish() {
    sys.n = sys.rho.size();
    sys.f = f.data();
  }
};

// Direct dense solve of (I - diag(rho) F) B = E per channel: Gaussian elimination with partial
// pivoting in double, the reference for the iterative solvers.
std::vector<Rgb> direct_solve(const RadiositySystem& s) {
  const size_t n = s.n;
  std::vector<Rgb> out(n);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> a(n * (n + 1));
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = 0; j < n; ++j)
        a[i * (n + 1) + j] = (i == j ? 1.0 : 0.0) - double(s.rho[i][c]) * s.f[i * n + j];
      a[i * (n + 1) + n] = s.emission[i][c];
    }
    for (size_t k = 0; k < n; ++k) {
      size_t p = k;
      for (size_t i = k + 1; i < n; ++i)
        if (std::fabs(a[i * (n + 1) + k]) > std::fabs(a[p * (n + 1) + k])) p = i;
      for (size_t j = 0; j <= n; ++j) std::swap(a[k * (n + 1) + j], a[p * (n + 1) + j]);
      for (size_t i = k + 1; i < n; ++i) {
        const double m = a[i * (n + 1) + k] / a[k * (n + 1) + k];
        for (size_t j = k; j <= n; ++j) a[i * (n + 1) + j] -= m * a[k * (n + 1) + j];
      }
    }
    std::vector<double> x(n);
    for (size_t i = n; i-- > 0;) {
      double v = a[i * (n + 1) + n];
      for (size_t j = i + 1; j < n; ++j) v -= a[i * (n + 1) + j] * x[j];
      x[i] = v / a[i * (n + 1) + i];
    }
    for (size_t i = 0; i < n; ++i) out[i][c] = static_cast<float>(x[i]);
  }
  return out;
}

// The lecture's example as a radiosity system: a source S (E = 1, black), and patches A, B.
// rho_A F_AS = 0.1 and rho_B F_BS = 0.2 (what S sends), rho_B F_BA = 0.4, rho_A F_AB = 0.05, so
// x = 0.1 + 0.05 y and y = 0.2 + 0.4 x. With rho = 0.5, 0.8 and areas 10, 5, 1 the matrix is
// reciprocal (A_i F_ij = A_j F_ji) with row sums <= 1.
OwnedSystem two_patch_example() {
  OwnedSystem o;
  // Rows: S, A, B. F_AS = 0.2, F_AB = 0.1, F_BS = 0.25, F_BA = 0.5; F_SA = 5 * 0.2 / 10,
  // F_SB = 1 * 0.25 / 10.
  o.f = {0, 0.1f, 0.025f, 0.2f, 0, 0.1f, 0.25f, 0.5f, 0};
  o.sys.rho = {Rgb(0), Rgb(0.5f), Rgb(0.8f)};
  o.sys.emission = {Rgb(1), Rgb(0), Rgb(0)};
  o.sys.area = {10, 5, 1};
  o.finish();
  return o;
}

// The inside of a sphere cut into elements: F_ij = A_j / sum A (reciprocal, rows sum to 1).
OwnedSystem sphere_enclosure(size_t n, uint32_t seed, Rgb rho, Rgb e) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.5f, 2.f);
  OwnedSystem o;
  o.sys.area.resize(n);
  double total = 0;
  for (float& a : o.sys.area) total += a = u(rng);
  o.f.resize(n * n);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) o.f[i * n + j] = static_cast<float>(o.sys.area[j] / total);
  o.sys.rho.assign(n, rho);
  o.sys.emission.assign(n, e);
  o.finish();
  return o;
}

// A random reciprocal system: symmetric A_i F_ij, scaled so that the largest row sum is 1;
// rho in [0.1, 0.9] per channel, a few emitters.
OwnedSystem random_system(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  OwnedSystem o;
  o.sys.area.resize(n);
  for (float& a : o.sys.area) a = 0.5f + 1.5f * u(rng);
  std::vector<double> g(n * n, 0.0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) g[i * n + j] = g[j * n + i] = u(rng);
  double max_row = 0;
  for (size_t i = 0; i < n; ++i) {
    double row = 0;
    for (size_t j = 0; j < n; ++j) row += g[i * n + j] / o.sys.area[i];
    max_row = std::max(max_row, row);
  }
  o.f.resize(n * n);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      o.f[i * n + j] = static_cast<float>(g[i * n + j] / o.sys.area[i] / max_row);
  o.sys.rho.resize(n);
  o.sys.emission.assign(n, Rgb(0));
  for (size_t i = 0; i < n; ++i) {
    o.sys.rho[i] = Rgb(0.1f + 0.8f * u(rng), 0.1f + 0.8f * u(rng), 0.1f + 0.8f * u(rng));
    if (u(rng) < 0.1f || i == 0) o.sys.emission[i] = Rgb(5 * u(rng), 5 * u(rng), 5 * u(rng));
  }
  o.finish();
  return o;
}

float max_abs_diff(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
  float m = 0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) m = std::max(m, std::fabs(a[i][c] - b[i][c]));
  return m;
}

SolveResult solve(const RadiositySystem& s, const std::string& method, double tol,
                  int max_iterations = 10000) {
  SolveOptions opt;
  opt.method = method;
  opt.tolerance = tol;
  opt.max_iterations = max_iterations;
  return solve_radiosity(s, opt);
}

TEST(RadiositySolver, LectureTwoPatchExample) {
  const OwnedSystem o = two_patch_example();
  for (const std::string& method : radiosity_solver_names()) {
    const SolveResult r = solve(o.sys, method, 1e-9);
    EXPECT_TRUE(r.converged) << method;
    EXPECT_NEAR(r.b[1].r, 11.0 / 98.0, 1e-6) << method;
    EXPECT_NEAR(r.b[2].g, 12.0 / 49.0, 1e-6) << method;
    EXPECT_NEAR(r.b[0].b, 1.0, 1e-6) << method;
    EXPECT_EQ(r.residuals.size(), size_t(r.iterations) + 1) << method;
  }
}

TEST(RadiositySolver, EnclosureGivesEOverOneMinusRho) {
  const Rgb rho(0.3f, 0.6f, 0.85f), e(1.f, 2.f, 0.5f);
  OwnedSystem sphere = sphere_enclosure(50, 3, rho, e);
  // A row-stochastic but not reciprocal matrix (random rows normalised to 1) has the same
  // solution; progressive must handle it too (it reads columns, not F_ij A_i / A_j).
  OwnedSystem stochastic = random_system(60, 4);
  for (size_t i = 0; i < stochastic.sys.n; ++i) {
    double row = 0;
    for (size_t j = 0; j < stochastic.sys.n; ++j) row += stochastic.f[i * stochastic.sys.n + j];
    for (size_t j = 0; j < stochastic.sys.n; ++j) stochastic.f[i * stochastic.sys.n + j] /= row;
  }
  stochastic.sys.rho.assign(stochastic.sys.n, rho);
  stochastic.sys.emission.assign(stochastic.sys.n, e);
  for (const OwnedSystem* o : {&sphere, &stochastic}) {
    for (const std::string& method : radiosity_solver_names()) {
      const SolveResult r = solve(o->sys, method, 1e-8);
      ASSERT_TRUE(r.converged) << method;
      for (const Rgb& b : r.b)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], e[c] / (1 - rho[c]), 2e-5) << method;
    }
  }
}

TEST(RadiositySolver, AllSolversAgreeWithDirectSolve) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const OwnedSystem o = random_system(120, seed);
    const std::vector<Rgb> exact = direct_solve(o.sys);
    float scale = 0;
    for (const Rgb& b : exact) scale = std::max(scale, b.max_channel());
    for (const std::string& method : radiosity_solver_names()) {
      const SolveResult r = solve(o.sys, method, 1e-7);
      ASSERT_TRUE(r.converged) << method << " seed " << seed;
      // |b - B*| <= residual * max E / (1 - 0.9): about 1e-6 relative, plus float rounding.
      EXPECT_LT(max_abs_diff(r.b, exact), 1e-5f * scale) << method << " seed " << seed;
    }
  }
}

TEST(RadiositySolver, GaussSeidelNeedsFewerIterationsThanJacobi) {
  const OwnedSystem o = random_system(150, 7);
  const SolveResult jacobi = solve(o.sys, "jacobi", 1e-8);
  const SolveResult gs = solve(o.sys, "gauss-seidel", 1e-8);
  ASSERT_TRUE(jacobi.converged && gs.converged);
  EXPECT_LT(gs.iterations, jacobi.iterations);
}

TEST(RadiositySolver, ResidualHistoriesDecrease) {
  const OwnedSystem o = random_system(100, 11);
  for (const char* method : {"jacobi", "gauss-seidel"}) {
    const SolveResult r = solve(o.sys, method, 1e-9);
    ASSERT_GE(r.residuals.size(), 3u) << method;
    for (size_t k = 1; k < r.residuals.size(); ++k)
      EXPECT_LE(r.residuals[k], r.residuals[k - 1] * (1 + 1e-9) + 1e-12) << method << " " << k;
  }
  // Progressive: not monotone shot by shot, but it gets there.
  const SolveResult p = solve(o.sys, "progressive", 1e-9);
  EXPECT_TRUE(p.converged);
  EXPECT_LT(p.residuals.back(), 1e-3 * p.residuals.front());
}

TEST(RadiositySolver, AmbientTermImprovesEarlyProgressiveEstimate) {
  // An enclosure with one bright element and varied reflectance: after 3 shots of 40, the
  // ambient-corrected display is closer to the solution than the plain estimate.
  OwnedSystem o = sphere_enclosure(40, 5, Rgb(0.6f), Rgb(0));
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.3f, 0.8f);
  for (Rgb& rho : o.sys.rho) rho = Rgb(u(rng), u(rng), u(rng));
  o.sys.emission[17] = Rgb(10.f);
  const std::vector<Rgb> exact = direct_solve(o.sys);
  SolveOptions opt;
  opt.method = "progressive";
  opt.shots_per_iteration = 3;
  opt.max_iterations = 1;
  const SolveResult r = solve_radiosity(o.sys, opt);
  ASSERT_EQ(r.ambient.size(), o.sys.n);
  std::vector<Rgb> display(o.sys.n);
  double plain = 0, corrected = 0;
  for (size_t i = 0; i < o.sys.n; ++i) {
    display[i] = r.b[i] + r.ambient[i];
    for (int c = 0; c < 3; ++c) {
      plain += std::pow(r.b[i][c] - exact[i][c], 2.0) * o.sys.area[i];
      corrected += std::pow(display[i][c] - exact[i][c], 2.0) * o.sys.area[i];
    }
  }
  EXPECT_LT(corrected, 0.25 * plain);
}

TEST(RadiositySolver, JacobiIsTheSameAtAnyThreadCount) {
  const OwnedSystem o = random_system(200, 13);
  SolveResult one, two;
  {
    ThreadLimit limit(1);
    one = solve(o.sys, "jacobi", 1e-6);
  }
  {
    ThreadLimit limit(2);
    two = solve(o.sys, "jacobi", 1e-6);
  }
  EXPECT_EQ(one.b, two.b);
  EXPECT_EQ(one.residuals, two.residuals);
}

TEST(RadiositySolver, UnknownMethodListsValidNames) {
  const OwnedSystem o = two_patch_example();
  SolveOptions opt;
  opt.method = "conjugate";
  try {
    solve_radiosity(o.sys, opt);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gauss-seidel"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("conjugate"), std::string::npos);
  }
}

TEST(RadiositySolver, IterationCapStopsUnconverged) {
  const OwnedSystem o = random_system(50, 17);
  const SolveResult r = solve(o.sys, "jacobi", 1e-12, 3);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_EQ(r.residuals.size(), 4u);
}

}  // namespace
}  // namespace penumbra
