/// Tests of the GGX microfacet distribution and the conductor and rough dielectric materials:
/// normalisation by quadrature, reciprocity, white-furnace albedo, chi-square goodness of fit of
/// the sampled directions, sample/eval/pdf consistency and parameter checking.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/material/conductor_material.h"
#include "penumbra/render/material/material_registry.h"
#include "penumbra/render/material/microfacet.h"
#include "penumbra/render/material/rough_dielectric_material.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

// The local direction at polar angle theta and azimuth phi (radians).
Vec3 direction(double theta, double phi) {
  return {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
          float(std::cos(theta))};
}

double radians(double degrees) {
  return degrees * kPi / 180.0;
}

// Integral of f(w) over the +z hemisphere by the midpoint rule in (s, phi) with theta = (pi/2) s^2,
// which puts most nodes near the pole where narrow lobes are (deterministic; the error of the
// rule falls as the square of the node spacing).
template <class F>
double integrate_hemisphere(F&& f, int n_s, int n_phi) {
  double sum = 0;
  for (int i = 0; i < n_s; ++i) {
    const double s = (i + 0.5) / n_s, theta = 0.5 * kPi * s * s;
    const double jacobian = std::sin(theta) * kPi * s / n_s * (2 * kPi / n_phi);
    for (int j = 0; j < n_phi; ++j)
      sum += f(direction(theta, (j + 0.5) * 2 * kPi / n_phi)) * jacobian;
  }
  return sum;
}

// The distributions checked below: isotropic at several roughness values, and anisotropic.
std::vector<MicrofacetDistribution> distributions() {
  std::vector<MicrofacetDistribution> all;
  for (float r : {0.05f, 0.1f, 0.3f, 0.6f, 1.0f})
    all.emplace_back(MicrofacetDistribution::roughness_to_alpha(r));
  all.emplace_back(0.05f, 0.5f);
  return all;
}

// Deterministic quadrature (no sampling): the rule's error here is below 2e-7, so 1e-5 leaves room
// only for float rounding.
TEST(Microfacet, DistributionIsNormalised) {
  for (const MicrofacetDistribution& dist : distributions()) {
    const double integral =
        integrate_hemisphere([&](Vec3 h) { return dist.d(h) * h.z; }, 2000, 512);
    EXPECT_NEAR(integral, 1.0, 1e-5) << "alpha " << dist.alpha_x() << " x " << dist.alpha_y();
  }
}

TEST(Microfacet, VisibleNormalDensityIntegratesToOne) {
  for (const MicrofacetDistribution& dist : distributions())
    for (double theta : {0.0, 30.0, 60.0, 85.0}) {
      const Vec3 w = direction(radians(theta), 0.7);
      const double integral =
          integrate_hemisphere([&](Vec3 h) { return dist.d_visible(w, h); }, 2000, 256);
      EXPECT_NEAR(integral, 1.0, 1e-5) << "alpha " << dist.alpha_x() << " theta " << theta;
    }
}

// Heights shared by the two directions help reflection and hinder transmission (Heitz 2014):
// G2_reflection >= G1 G1 >= G2_transmission, with equality when one direction is the normal.
TEST(Microfacet, HeightCorrelationOrdersTheMaskingForms) {
  const MicrofacetDistribution dist(0.5f);
  Pcg32 rng(11);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 a = direction(std::acos(rng.next_double()), 2 * kPi * rng.next_double());
    const Vec3 b = direction(std::acos(rng.next_double()), 2 * kPi * rng.next_double());
    const float separable = dist.g1(a) * dist.g1(b);
    EXPECT_GE(dist.g2_reflection(a, b), separable * (1 - 1e-6f));
    EXPECT_LE(dist.g2_transmission(a, b), separable * (1 + 1e-5f));
    EXPECT_NEAR(dist.g2_transmission(a, {0, 0, 1}), dist.g1(a), 1e-6f);
    EXPECT_NEAR(dist.g2_reflection(a, {0, 0, 1}), dist.g1(a), 1e-6f);
  }
  EXPECT_NEAR(dist.g2_transmission({0, 0, 1}, {0, 0, 1}), 1.0f, 1e-6f);  // B(1, 1) = 1
}

TEST(Conductor, FresnelMatchesClosedForms) {
  // Normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
  const Rgb eta(0.2f, 0.9f, 1.1f), k(3.9f, 2.4f, 2.1f);
  const Rgb f = fresnel_conductor(1.0f, eta, k);
  for (int c = 0; c < 3; ++c) {
    const float n = eta[c], kc = k[c];
    EXPECT_NEAR(f[c], ((n - 1) * (n - 1) + kc * kc) / ((n + 1) * (n + 1) + kc * kc), 1e-6f);
  }
  // k = 0 is a dielectric; grazing incidence reflects everything.
  for (float c : {1.0f, 0.7f, 0.3f, 0.05f})
    EXPECT_NEAR(fresnel_conductor(c, Rgb(1.5f), Rgb(0.0f)).g, fresnel_dielectric(c, 1.5f), 1e-6f);
  EXPECT_NEAR(fresnel_conductor(0.0f, eta, k).r, 1.0f, 1e-6f);
  EXPECT_NEAR(fresnel_schlick(1.0f, Rgb(0.3f)).r, 0.3f, 1e-7f);
  EXPECT_NEAR(fresnel_schlick(0.0f, Rgb(0.3f)).r, 1.0f, 1e-7f);
}

// Uniform random direction on the sphere.
Vec3 random_direction(Pcg32& rng) {
  return direction(std::acos(1 - 2 * rng.next_double()), 2 * kPi * rng.next_double());
}

// |a - b| relative to the larger.
float relative_difference(float a, float b) {
  return std::fabs(a - b) / std::max({std::fabs(a), std::fabs(b), 1e-30f});
}

TEST(Conductor, IsReciprocal) {
  Pcg32 rng(5);
  for (float r : {0.2f, 0.5f, 1.0f}) {
    const ConductorMaterial m(
        ConductorFresnel::complex_ior(Rgb(0.2f, 0.9f, 1.1f), Rgb(3.9f, 2.4f, 2.1f)), r);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = random_direction(rng), wi = random_direction(rng);
      const Rgb a = m.eval(wo, wi), b = m.eval(wi, wo);
      for (int c = 0; c < 3; ++c) ASSERT_LE(relative_difference(a[c], b[c]), 1e-4f);
      EXPECT_EQ(a.is_black(), !same_hemisphere(wo, wi));
    }
  }
}

// Reflection is reciprocal. For transmission with the radiance convention, f_t = eta_o^2 Q with Q
// symmetric (Walter et al. 2007; eta_o the index on wo's side), so
// f_t(wo, wi) / eta_o^2 = f_t(wi, wo) / eta_i^2 (Veach 1997, thesis, chapter 5).
TEST(RoughDielectric, ObeysGeneralisedReciprocity) {
  Pcg32 rng(6);
  const float ior = 1.5f;
  for (float r : {0.2f, 0.5f, 1.0f}) {
    const RoughDielectricMaterial m(ior, r, Rgb(0.9f, 0.8f, 0.7f));
    int transmissions = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec3 wo = random_direction(rng), wi = random_direction(rng);
      const float eta_o = wo.z > 0 ? 1.0f : ior, eta_i = wi.z > 0 ? 1.0f : ior;
      // Skip microfacets seen within ~1 degree of grazing (|cos| < 0.02) from either side: the
      // Fresnel factor's infinite slope at the critical angle turns float rounding of the
      // directions into relative differences of up to 1e-2 there.
      const Vec3 h = normalize(wo * eta_o + wi * eta_i);
      if (std::fabs(dot(wo, h)) < 0.02f || std::fabs(dot(wi, h)) < 0.02f) continue;
      const Rgb a = m.eval(wo, wi) * (1 / (eta_o * eta_o));
      const Rgb b = m.eval(wi, wo) * (1 / (eta_i * eta_i));
      for (int c = 0; c < 3; ++c) ASSERT_LE(relative_difference(a[c], b[c]), 1e-3f) << r;
      transmissions += !same_hemisphere(wo, wi) && !a.is_black();
    }
    EXPECT_GT(transmissions, 100);  // the transmission branch was exercised
  }
}

// Mean and standard error of a material's directional albedo from wo with its own sampling:
// weights f |cos i| / pdf, transmitted ones times eta^2 (eta = index on wi's side / wo's side)
// when `flux`, which undoes the radiance scaling and measures transported power.
struct Estimate {
  double mean = 0, se = 0, transmitted = 0;
};

Estimate albedo(const Material& m, Vec3 wo, float ior, bool flux, int n, uint64_t seed) {
  Pcg32 rng(seed);
  double sum = 0, sum2 = 0, sum_t = 0;
  for (int i = 0; i < n; ++i) {
    const auto s = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
    if (!s) continue;
    double w = s->f.g * std::fabs(s->wi.z) / s->pdf;
    if (!same_hemisphere(wo, s->wi)) {
      const double eta = wo.z > 0 ? ior : 1.0 / ior;
      if (flux) w *= eta * eta;
      sum_t += w;
    }
    sum += w, sum2 += w * w;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n), sum_t / n};
}

constexpr double kSigmas = 5;       // bounds at 5 standard errors: a false alarm has p < 6e-7
constexpr double kRounding = 1e-5;  // float rounding of weights that are exactly 1 in theory
constexpr int kFurnaceSamples = 40000;

// Directional albedo of a reflecting material by deterministic quadrature over microfacet normals,
// independent of sample() and pdf(): h reflects wo into wi = reflect(wo, h) with dwi = 4 (wo.h) dh,
// so E = integral of f(wo, wi(h)) cos(wi) 4 (wo.h) dh over the normals facing wo (500 x 64 nodes:
// within 1e-4 of a 4000 x 512 grid for every case below).
double reflection_albedo_by_quadrature(const Material& m, Vec3 wo) {
  return integrate_hemisphere(
      [&](Vec3 h) {
        const float wo_h = dot(wo, h);
        const Vec3 wi = reflect(wo, h);
        if (!(wo_h > 0.0f) || !(wi.z > 0.0f)) return 0.0;
        return double(m.eval(wo, wi).g) * wi.z * 4.0 * wo_h;
      },
      500, 64);
}

// With F = 1 the sample weight is G2 / G1(wo) in [0, 1]: the albedo is at most 1, and what it
// misses is the light scattered more than once between microfacets, which the single-scattering
// model drops (Heitz et al. 2016, "Multiple-Scattering Microfacet BSDFs with the Smith Model").
// The estimate from sample() must match the quadrature of eval() within 5 standard errors plus the
// quadrature's error; the expected loss, measured by that quadrature, is at most 2% for roughness
// <= 0.2 up to 75 degrees and at most 10% up to 89 degrees (the bounds asserted). At roughness 1
// and normal incidence the albedo is exactly 1 - ln 2 = 0.3069: D = 1/pi, visible normals have
// density mu/pi, wi.z = 2 mu^2 - 1 > 0 needs mu > 1/sqrt(2), G2/G1 = 2 wi.z / (1 + wi.z), and
// the integral of 2 (2 mu^2 - 1) / mu over [1/sqrt(2), 1] is 1 - ln 2.
TEST(Conductor, WhiteFurnaceAlbedo) {
  const double thetas[] = {0, 45, 75, 85, 89};
  for (float r : {0.05f, 0.1f, 0.2f, 0.5f, 1.0f}) {
    const ConductorMaterial m(ConductorFresnel::schlick_f0(Rgb(1.0f)), r);
    std::printf("conductor F=1 roughness %.2f albedo (quadrature / sampled):", r);
    for (double theta : thetas) {
      const Vec3 wo = direction(radians(theta), 0.3);
      const double quadrature = reflection_albedo_by_quadrature(m, wo);
      const Estimate e = albedo(m, wo, 1.0f, false, kFurnaceSamples, 7 + uint64_t(theta));
      std::printf(" %.0f deg %.4f / %.4f;", theta, quadrature, e.mean);
      EXPECT_NEAR(e.mean, quadrature, kSigmas * e.se + 1e-3) << r << " " << theta;
      EXPECT_LE(quadrature, 1 + 1e-3);
      if (r <= 0.2f) {
        EXPECT_GE(quadrature, theta <= 75 ? 0.98 : 0.9) << r << " " << theta;
      }
      if (r == 1.0f && theta == 0) {
        EXPECT_NEAR(quadrature, 1 - std::log(2.0), 1e-3);
      }
    }
    std::printf("\n");
  }
}

// Reflected plus transmitted power (flux weights) never exceeds one, from either side, and at
// low roughness approaches the smooth interface: reflection F(cos), total 1.
TEST(RoughDielectric, WhiteFurnaceAlbedo) {
  const float ior = 1.5f;
  const double thetas[] = {0, 45, 80, 180, 150, 120, 100};  // > 90: wo inside
  for (float r : {0.05f, 0.3f, 0.6f, 1.0f}) {
    const RoughDielectricMaterial m(ior, r, Rgb(1.0f));
    std::printf("rough_dielectric ior 1.5 roughness %.2f R+T:", r);
    for (double theta : thetas) {
      const Vec3 wo = direction(radians(theta), 1.1);
      const Estimate e = albedo(m, wo, ior, true, kFurnaceSamples, 17 + uint64_t(theta));
      std::printf(" %.0f deg %.4f;", theta, e.mean);
      EXPECT_LE(e.mean, 1 + kSigmas * e.se + kRounding) << r << " " << theta;
      if (r == 0.05f) {
        // Reflection is chosen with probability ~F and weighs ~1: binomial standard error, plus
        // 2e-3 for the lobe's width (alpha = 0.0025).
        const double fr = fresnel_dielectric(wo.z, ior), reflected = e.mean - e.transmitted;
        std::printf(" (R %.4f, F %.4f)", reflected, fr);
        EXPECT_NEAR(reflected, fr, kSigmas * std::sqrt(fr * (1 - fr) / kFurnaceSamples) + 2e-3)
            << theta;
        if (std::fabs(wo.z) > 0.3) {
          EXPECT_GE(e.mean, 0.99 - kSigmas * e.se) << theta;
        }
      }
    }
    std::printf("\n");
  }
}

// Regularised upper incomplete gamma function Q(a, x): the series for P when x < a + 1, else the
// continued fraction by the modified Lentz method (Press et al., "Numerical Recipes", 6.2).
double gamma_q(double a, double x) {
  if (x <= 0) return 1;
  const double prefactor = std::exp(-x + a * std::log(x) - std::lgamma(a));
  if (x < a + 1) {
    double term = 1 / a, sum = term;
    for (int n = 1; n < 10000 && term > sum * 1e-16; ++n) sum += term *= x / (a + n);
    return 1 - prefactor * sum;
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    c = b + an / c;
    d = 1 / (std::fabs(d) < kTiny ? kTiny : d);
    c = std::fabs(c) < kTiny ? kTiny : c;
    h *= d * c;
    if (std::fabs(d * c - 1) < 1e-16) break;
  }
  return prefactor * h;
}

struct ChiSquare {
  double chi2 = 0, p = 0;
  int dof = 0;
};

// Integral of m.pdf(wo, .) over the patch [t0, t1] x [p0, p1] of (theta, phi) by an 8 x 8 midpoint
// rule, and whether the patch straddles the edge of the pdf's support (some nodes zero, some not).
struct PatchIntegral {
  double value = 0;
  bool straddles = false;
};

PatchIntegral patch_integral(const Material& m, Vec3 wo, double t0, double t1, double p0,
                             double p1) {
  constexpr int kGrid = 8;
  const double dt = (t1 - t0) / kGrid, dp = (p1 - p0) / kGrid;
  double sum = 0;
  int zeros = 0;
  for (int a = 0; a < kGrid; ++a) {
    const double theta = t0 + (a + 0.5) * dt;
    for (int b = 0; b < kGrid; ++b) {
      const float pdf = m.pdf(wo, direction(theta, p0 + (b + 0.5) * dp));
      sum += pdf * std::sin(theta);
      zeros += pdf == 0.0f;
    }
  }
  return {sum * dt * dp, zeros > 0 && zeros < kGrid * kGrid};
}

// Adaptive refinement of a patch: the four quadrants are integrated and refined further (up to
// `depth` levels), always for the first `levels` levels, then where they change the patch's
// estimate by more than `tol` or straddle the edge of the support. The pdf of a rough dielectric
// jumps there (microfacet normals reaching the horizon, where D is not zero), and a midpoint rule
// converges slowly and erratically across a jump: without refining there, expected counts were
// off by up to 0.06% of all samples.
double adaptive_integral(const Material& m, Vec3 wo, double t0, double t1, double p0, double p1,
                         const PatchIntegral& whole, double tol, int depth, int levels) {
  const double tm = 0.5 * (t0 + t1), pm = 0.5 * (p0 + p1);
  const PatchIntegral q[4] = {
      patch_integral(m, wo, t0, tm, p0, pm), patch_integral(m, wo, tm, t1, p0, pm),
      patch_integral(m, wo, t0, tm, pm, p1), patch_integral(m, wo, tm, t1, pm, p1)};
  const double sum = q[0].value + q[1].value + q[2].value + q[3].value;
  const bool straddles =
      whole.straddles || q[0].straddles || q[1].straddles || q[2].straddles || q[3].straddles;
  if (depth == 0 || (levels <= 0 && !straddles && std::fabs(sum - whole.value) <= tol)) return sum;
  return adaptive_integral(m, wo, t0, tm, p0, pm, q[0], tol / 4, depth - 1, levels - 1) +
         adaptive_integral(m, wo, tm, t1, p0, pm, q[1], tol / 4, depth - 1, levels - 1) +
         adaptive_integral(m, wo, t0, tm, pm, p1, q[2], tol / 4, depth - 1, levels - 1) +
         adaptive_integral(m, wo, tm, t1, pm, p1, q[3], tol / 4, depth - 1, levels - 1);
}

// Pearson's chi-square test of `n` samples of m.sample(wo, ...) against m.pdf(wo, .) on 10 theta x
// 20 phi bins of the sphere plus one cell for rejected samples (expected: n (1 - integral of the
// pdf)). Expected counts integrate the pdf over each bin adaptively (at least 32 x 32 nodes, to
// 1e-6: 0.4 of the 400,000 samples); cells with expected counts below 5 are pooled (into the
// smallest other cell if the pool stays below 5). Degrees of freedom: cells - 1 (nothing is
// estimated from the data).
ChiSquare chi_square(const Material& m, Vec3 wo, int n, uint64_t seed) {
  constexpr int kTheta = 10, kPhi = 20;
  const double dt = kPi / kTheta, dp = 2 * kPi / kPhi;
  std::vector<double> expected(kTheta * kPhi + 1, 0.0), observed(kTheta * kPhi + 1, 0.0);
  double total = 0;
  // wo lies in the xz plane and the materials are isotropic: the pdf is symmetric under y -> -y,
  // which maps bin j to bin kPhi - 1 - j, so half the bins are integrated.
  EXPECT_EQ(wo.y, 0.0f);
  for (int i = 0; i < kTheta; ++i)
    for (int j = 0; j < kPhi / 2; ++j) {
      const double t0 = i * dt, t1 = t0 + dt, p0 = j * dp, p1 = p0 + dp;
      const double integral = adaptive_integral(m, wo, t0, t1, p0, p1,
                                                patch_integral(m, wo, t0, t1, p0, p1), 1e-6, 6, 2);
      expected[i * kPhi + j] = expected[i * kPhi + kPhi - 1 - j] = integral * n;
      total += 2 * integral;
    }
  expected.back() = std::max(0.0, 1 - total) * n;
  Pcg32 rng(seed);
  for (int k = 0; k < n; ++k) {
    const auto s = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
    if (!s) {
      observed.back() += 1;
      continue;
    }
    const double theta = std::acos(std::clamp(double(s->wi.z), -1.0, 1.0));
    double phi = std::atan2(double(s->wi.y), double(s->wi.x));
    if (phi < 0) phi += 2 * kPi;
    const int i = std::min(kTheta - 1, int(theta / dt)), j = std::min(kPhi - 1, int(phi / dp));
    observed[i * kPhi + j] += 1;
  }
  // Pool the small cells, then sum (O - E)^2 / E.
  std::vector<std::pair<double, double>> cells;
  double pool_e = 0, pool_o = 0;
  for (size_t c = 0; c < expected.size(); ++c)
    if (expected[c] < 5)
      pool_e += expected[c], pool_o += observed[c];
    else
      cells.push_back({expected[c], observed[c]});
  if (pool_e >= 5 || cells.empty()) {
    cells.push_back({pool_e, pool_o});
  } else {
    auto smallest = std::min_element(cells.begin(), cells.end());
    smallest->first += pool_e, smallest->second += pool_o;
  }
  ChiSquare result;
  for (const auto& [e, o] : cells) result.chi2 += (o - e) * (o - e) / e;
  result.dof = int(cells.size()) - 1;
  result.p = gamma_q(0.5 * result.dof, 0.5 * result.chi2);
  return result;
}

TEST(Microfacet, ChiSquarePValueMatchesTables) {
  // 0.999 quantiles: 43.82 for 19 degrees of freedom, 10.83 for 1, 149.45 for 100.
  EXPECT_NEAR(gamma_q(9.5, 43.82 / 2), 1e-3, 2e-6);
  EXPECT_NEAR(gamma_q(0.5, 10.83 / 2), 1e-3, 2e-6);
  EXPECT_NEAR(gamma_q(50, 149.45 / 2), 1e-3, 2e-6);
}

constexpr double kSignificance = 1e-3;
constexpr int kChiSquareSamples = 400000;

// Sampled directions follow pdf(): per configuration, p >= 1e-3 (fixed seeds).
TEST(Conductor, ChiSquareSamplesFollowPdf) {
  const auto fresnel = ConductorFresnel::complex_ior(Rgb(0.2f, 0.9f, 1.1f), Rgb(3.9f, 2.4f, 2.1f));
  for (float r : {0.3f, 0.6f, 1.0f})
    for (double theta : {10.0, 50.0, 80.0, 130.0}) {  // 130: the back side
      const ConductorMaterial m(fresnel, r);
      const ChiSquare t =
          chi_square(m, direction(radians(theta), 0.0), kChiSquareSamples, 31 + uint64_t(theta));
      std::printf("conductor roughness %.1f theta %3.0f: chi2 %.1f dof %d p %.3f\n", r, theta,
                  t.chi2, t.dof, t.p);
      EXPECT_GE(t.p, kSignificance) << r << " " << theta;
    }
}

TEST(RoughDielectric, ChiSquareSamplesFollowPdf) {
  for (float r : {0.3f, 0.6f, 1.0f})
    for (double theta : {20.0, 70.0, 160.0, 120.0}) {  // > 90: wo inside; 120 is past the
                                                       // critical angle (41.8 degrees)
      const RoughDielectricMaterial m(1.5f, r, Rgb(1.0f));
      const ChiSquare t =
          chi_square(m, direction(radians(theta), 0.0), kChiSquareSamples, 37 + uint64_t(theta));
      std::printf("rough_dielectric roughness %.1f theta %3.0f: chi2 %.1f dof %d p %.3f\n", r,
                  theta, t.chi2, t.dof, t.p);
      EXPECT_GE(t.p, kSignificance) << r << " " << theta;
    }
}

// A sample's value and density are what eval() and pdf() give for its direction.
void expect_consistent(const Material& m, Vec3 wo, uint64_t seed) {
  Pcg32 rng(seed);
  int accepted = 0;
  for (int i = 0; i < 4000; ++i) {
    const auto s = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
    if (!s) continue;
    ++accepted;
    ASSERT_FALSE(s->is_specular());
    ASSERT_NEAR(length(s->wi), 1.0f, 1e-5f);
    ASSERT_LE(relative_difference(s->pdf, m.pdf(wo, s->wi)), 1e-3f);
    const Rgb f = m.eval(wo, s->wi);
    for (int c = 0; c < 3; ++c) ASSERT_LE(relative_difference(s->f[c], f[c]), 1e-3f);
  }
  EXPECT_GT(accepted, 2000);
}

TEST(Conductor, SamplesAgreeWithEvalAndPdf) {
  const auto fresnel = ConductorFresnel::complex_ior(Rgb(0.2f, 0.9f, 1.1f), Rgb(3.9f, 2.4f, 2.1f));
  for (float r : {0.05f, 0.3f, 1.0f})
    for (double theta : {0.0, 60.0, 88.0, 120.0})
      expect_consistent(ConductorMaterial(fresnel, r), direction(radians(theta), 2.0), 41);
}

TEST(RoughDielectric, SamplesAgreeWithEvalAndPdf) {
  for (float r : {0.05f, 0.3f, 1.0f})
    for (double theta : {0.0, 60.0, 88.0, 120.0, 170.0})
      expect_consistent(RoughDielectricMaterial(1.5f, r, Rgb(0.5f, 0.7f, 0.9f)),
                        direction(radians(theta), 2.0), 43);
}

// Roughness 0 (alpha < 1e-3) scatters through delta lobes, as the smooth materials do.
TEST(RoughDielectric, ZeroRoughnessIsSmooth) {
  const Vec3 wo = direction(radians(40), 0.5);
  const RoughDielectricMaterial rough(1.5f, 0.0f, Rgb(0.8f));
  const DielectricMaterial smooth(1.5f, Rgb(0.8f));
  EXPECT_FALSE(rough.has_non_specular());
  SpecularLobe a[2], b[2];
  ASSERT_EQ(rough.specular_lobes(wo, a), smooth.specular_lobes(wo, b));
  EXPECT_EQ(a[1].weight, b[1].weight);
  EXPECT_TRUE(rough.eval(wo, -wo).is_black());
  EXPECT_TRUE(RoughDielectricMaterial(1.5f, 0.05f, Rgb(1.0f)).has_non_specular());
}

TEST(Conductor, ZeroRoughnessIsAMirror) {
  const ConductorMaterial m(ConductorFresnel::schlick_f0(Rgb(0.5f)), 0.0f);
  EXPECT_FALSE(m.has_non_specular());
  const Vec3 wo = direction(radians(60), 0.5);
  SpecularLobe lobes[2];
  ASSERT_EQ(m.specular_lobes(wo, lobes), 1);
  EXPECT_NEAR(lobes[0].wi.x, -wo.x, 1e-7f);
  EXPECT_NEAR(lobes[0].weight.r, fresnel_schlick(0.5f, Rgb(0.5f)).r, 1e-6f);
  const auto s = m.sample(wo, 0.5f, {0.5f, 0.5f});
  ASSERT_TRUE(s && s->is_specular());
  EXPECT_NEAR(s->f.r * s->wi.z / s->pdf, lobes[0].weight.r, 1e-6f);
  EXPECT_EQ(ConductorMaterial(ConductorFresnel::schlick_f0(Rgb(0.5f)), 0.04f).has_non_specular(),
            true);
}

SceneParams params(const std::string& json_text) {
  return SceneParams(nlohmann::json::parse(json_text), "scene.json", "/materials/m");
}

TEST(Conductor, RejectsBadParameters) {
  for (const char* bad : {
           R"({"type": "conductor", "reflectance": 0.9, "roughness": 1.5})",
           R"({"type": "conductor", "reflectance": 0.9, "roughness": -0.1})",
           R"({"type": "conductor", "reflectance": 0.9, "eta": 0.2, "k": 3.9})",
           R"({"type": "conductor", "roughness": 0.2})",
           R"({"type": "conductor", "eta": 0.2})",
           R"({"type": "conductor", "eta": [0.2, 0.9, -1], "k": 3.9})",
           R"({"type": "conductor", "reflectance": 1.2})",
           R"({"type": "conductor", "reflectance": 0.9, "rougness": 0.2})",
       })
    EXPECT_THROW(make_material(params(bad)), InputError) << bad;
  const auto gold = make_material(
      params(R"({"type": "conductor", "eta": [0.143, 0.375, 1.442], "k": [3.983, 2.386, 1.603]})"));
  EXPECT_TRUE(gold->has_non_specular());  // default roughness 0.3
  EXPECT_NEAR(gold->albedo().r, fresnel_conductor(1, Rgb(0.143f), Rgb(3.983f)).r, 1e-6f);
  EXPECT_NO_THROW(
      make_material(params(R"({"type": "conductor", "reflectance": 1, "roughness": 0})")));
}

TEST(RoughDielectric, RejectsBadParameters) {
  for (const char* bad : {
           R"({"type": "rough_dielectric", "roughness": 1.5})",
           R"({"type": "rough_dielectric", "roughness": -0.5})",
           R"({"type": "rough_dielectric", "ior": 0})",
           R"({"type": "rough_dielectric", "tint": 2})",
           R"({"type": "rough_dielectric", "eta": 1.5})",
       })
    EXPECT_THROW(make_material(params(bad)), InputError) << bad;
  EXPECT_NO_THROW(
      make_material(params(R"({"type": "rough_dielectric", "ior": 1.33, "roughness": 0.4,
      "tint": [0.9, 0.95, 1]})")));
}

}  // namespace
}  // namespace penumbra
