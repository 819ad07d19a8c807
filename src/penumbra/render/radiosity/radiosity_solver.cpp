#include "penumbra/render/radiosity/radiosity_solver.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"

namespace penumbra {

namespace {

// Radiosity in double inside the solvers, so that the residual can fall well below float's
// resolution (1e-7 relative) and the tolerance is not limited by the storage of B.
struct D3 {
  double c[3] = {0, 0, 0};
};

D3 to_d3(Rgb v) {
  return {{v.r, v.g, v.b}};
}
Rgb to_rgb(const D3& v) {
  return {static_cast<float>(v.c[0]), static_cast<float>(v.c[1]), static_cast<float>(v.c[2])};
}
double abs_luminance(const D3& v) {
  return 0.2126 * std::fabs(v.c[0]) + 0.7152 * std::fabs(v.c[1]) + 0.0722 * std::fabs(v.c[2]);
}

// Rows handed to one task: enough work (>= 64 rows of n floats) to amortise the scheduling.
constexpr size_t kRowGrain = 64;

// sum_j F_ij b_j over one row, in element order (fixed order: the same bits at any thread count).
D3 row_product(const float* row, const std::vector<D3>& b) {
  double s0 = 0, s1 = 0, s2 = 0;
  const size_t n = b.size();
  for (size_t j = 0; j < n; ++j) {
    const double f = row[j];
    s0 += f * b[j].c[0];
    s1 += f * b[j].c[1];
    s2 += f * b[j].c[2];
  }
  return {{s0, s1, s2}};
}

// r_i = E_i + rho_i (F b)_i - b_i for every row, in parallel (rows are independent).
void residual_vector(const RadiositySystem& sys, const std::vector<D3>& b, std::vector<D3>& r) {
  const size_t n = sys.n;
  r.resize(n);
  parallel_for_range(
      n,
      [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
          const D3 s = row_product(sys.f + i * n, b);
          for (int c = 0; c < 3; ++c)
            r[i].c[c] = double(sys.emission[i][c]) + double(sys.rho[i][c]) * s.c[c] - b[i].c[c];
        }
      },
      kRowGrain);
}

double max_abs_luminance(const std::vector<D3>& r) {
  double m = 0;
  for (const D3& v : r) m = std::max(m, abs_luminance(v));
  return m;
}

// The residual's normaliser: the brightest emitter (1 when nothing emits: absolute residual).
double residual_scale(const RadiositySystem& sys) {
  double m = 0;
  for (Rgb e : sys.emission) m = std::max(m, abs_luminance(to_d3(e)));
  return m > 0 ? m : 1.0;
}

void validate(const RadiositySystem& sys, bool need_area) {
  const auto bad = [](const std::string& what) { throw Error("radiosity solver: " + what); };
  if (sys.n > 0 && sys.f == nullptr) bad("the form-factor matrix is null");
  if (sys.rho.size() != sys.n)
    bad("rho has " + std::to_string(sys.rho.size()) + " entries, expected " +
        std::to_string(sys.n));
  if (sys.emission.size() != sys.n)
    bad("emission has " + std::to_string(sys.emission.size()) + " entries, expected " +
        std::to_string(sys.n));
  if (need_area && sys.area.size() != sys.n)
    bad("progressive refinement needs the areas: area has " + std::to_string(sys.area.size()) +
        " entries, expected " + std::to_string(sys.n));
}

// Everything a solver loop needs: the iterate, the history, the stopping rule.
struct Run {
  const RadiositySystem& sys;
  const SolveOptions& opt;
  double scale;
  std::vector<D3> b;
  SolveResult result;

  // Records the relative residual of the current iterate; true when it is below the tolerance.
  bool record(double absolute) {
    const double rel = absolute / scale;
    result.residuals.push_back(rel);
    result.converged = rel <= opt.tolerance;
    return result.converged;
  }
  bool more() const { return !result.converged && result.iterations < opt.max_iterations; }
};

// Jacobi: b <- b + r / (1 - rho_i F_ii). Each pass computes r of the current iterate, which is both
// its residual (recorded) and the update, so one matrix pass per iteration. Parallel over rows.
void solve_jacobi(Run& run) {
  const RadiositySystem& sys = run.sys;
  std::vector<D3> r;
  for (;;) {
    residual_vector(sys, run.b, r);
    if (run.record(max_abs_luminance(r)) || run.result.iterations >= run.opt.max_iterations) break;
    parallel_for(sys.n, [&](size_t i) {
      for (int c = 0; c < 3; ++c)
        run.b[i].c[c] += r[i].c[c] / (1.0 - double(sys.rho[i][c]) * sys.f[i * sys.n + i]);
    });
    ++run.result.iterations;
  }
}

// Gauss-Seidel: rows in element order, each solved exactly for b_i with the newest values of the
// others. Sequential by nature (row i needs rows < i of this sweep); the residual pass after
// each sweep is parallel.
void solve_gauss_seidel(Run& run) {
  const RadiositySystem& sys = run.sys;
  const size_t n = sys.n;
  std::vector<D3> r;
  residual_vector(sys, run.b, r);
  run.record(max_abs_luminance(r));
  while (run.more()) {
    for (size_t i = 0; i < n; ++i) {
      const float* row = sys.f + i * n;
      D3 s = row_product(row, run.b);
      for (int c = 0; c < 3; ++c) {
        const double rho = sys.rho[i][c];
        const double others = s.c[c] - row[i] * run.b[i].c[c];
        run.b[i].c[c] = (sys.emission[i][c] + rho * others) / (1.0 - rho * row[i]);
      }
    }
    ++run.result.iterations;
    residual_vector(sys, run.b, r);
    run.record(max_abs_luminance(r));
  }
}

// Progressive refinement (Cohen et al. 1988), a Southwell relaxation: b starts at E and the
// unshot radiosity db at E; each shot takes the element with the largest unshot power
// A_i lum(db_i), and every j receives rho_j F_ji db_i (into b_j and db_j). The invariant is
// r = rho F db, so the residual is reported from b after each batch of shots. Sequential by nature
// (each shot depends on the previous). Shooting reads column i of F; a transposed copy (n^2
// floats) makes that a contiguous row, instead of F_ji = F_ij A_i / A_j (Cohen et al.), which
// would equal the gathering solvers' fixed point only for an exactly reciprocal F.
void solve_progressive(Run& run) {
  const RadiositySystem& sys = run.sys;
  const size_t n = sys.n;
  check_memory(double(n) * double(n) * sizeof(float),
               fmt::format("radiosity: the progressive solver's transposed copy of the {} x {} "
                           "form-factor matrix",
                           n, n),
               "use another solver or fewer elements");
  std::vector<float> ft(n * n);
  parallel_for(n, [&](size_t i) {
    for (size_t j = 0; j < n; ++j) ft[i * n + j] = sys.f[j * n + i];
  });
  std::vector<D3> db = run.b, r;
  const size_t shots = run.opt.shots_per_iteration > 0 ? run.opt.shots_per_iteration : n;
  residual_vector(sys, run.b, r);
  run.record(max_abs_luminance(r));
  bool exhausted = false;
  while (run.more() && !exhausted) {
    for (size_t k = 0; k < shots; ++k) {
      // The shooter: largest unshot power (first such element on ties).
      size_t best = n;
      double best_power = 0;
      for (size_t i = 0; i < n; ++i) {
        const double power = sys.area[i] * abs_luminance(db[i]);
        if (power > best_power) best_power = power, best = i;
      }
      if (best == n) {
        exhausted = true;
        break;
      }
      const D3 shot = db[best];
      db[best] = D3{};
      const float* col = ft.data() + best * n;  // col[j] = F_j,best
      for (size_t j = 0; j < n; ++j) {
        for (int c = 0; c < 3; ++c) {
          const double add = double(sys.rho[j][c]) * col[j] * shot.c[c];
          run.b[j].c[c] += add;
          db[j].c[c] += add;
        }
      }
    }
    ++run.result.iterations;
    residual_vector(sys, run.b, r);
    run.record(max_abs_luminance(r));
  }
  // The ambient term (Cohen et al. 1988, section 4): the unshot radiosity, area-averaged and
  // multiplied by the interreflection factor R = 1 / (1 - average reflectance).
  double total_area = 0;
  D3 unshot, rho_avg;
  for (size_t i = 0; i < n; ++i) {
    total_area += sys.area[i];
    for (int c = 0; c < 3; ++c) {
      unshot.c[c] += db[i].c[c] * sys.area[i];
      rho_avg.c[c] += double(sys.rho[i][c]) * sys.area[i];
    }
  }
  run.result.ambient.resize(n);
  if (total_area <= 0) return;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double ambient = unshot.c[c] / total_area / (1.0 - rho_avg.c[c] / total_area);
      run.result.ambient[i][c] = static_cast<float>(double(sys.rho[i][c]) * ambient);
    }
  }
}

}  // namespace

const std::vector<std::string>& radiosity_solver_names() {
  static const std::vector<std::string> names = {"jacobi", "gauss-seidel", "progressive"};
  return names;
}

double radiosity_residual(const RadiositySystem& system, const std::vector<Rgb>& b) {
  validate(system, false);
  std::vector<D3> bd(b.size()), r;
  std::transform(b.begin(), b.end(), bd.begin(), to_d3);
  residual_vector(system, bd, r);
  return max_abs_luminance(r) / residual_scale(system);
}

SolveResult solve_radiosity(const RadiositySystem& system, const SolveOptions& options) {
  const auto& names = radiosity_solver_names();
  if (std::find(names.begin(), names.end(), options.method) == names.end()) {
    std::string list;
    for (const auto& name : names) list += (list.empty() ? "" : ", ") + name;
    throw Error("radiosity solver: unknown method '" + options.method + "' (valid: " + list + ")");
  }
  const bool progressive = options.method == "progressive";
  validate(system, progressive);
  Timer timer;
  Run run{system, options, residual_scale(system), {}, {}};
  run.b.resize(system.n);
  std::transform(system.emission.begin(), system.emission.end(), run.b.begin(), to_d3);
  if (options.method == "jacobi")
    solve_jacobi(run);
  else if (options.method == "gauss-seidel")
    solve_gauss_seidel(run);
  else
    solve_progressive(run);
  run.result.b.resize(system.n);
  std::transform(run.b.begin(), run.b.end(), run.result.b.begin(), to_rgb);
  run.result.seconds = timer.elapsed_s();
  return std::move(run.result);
}

}  // namespace penumbra
