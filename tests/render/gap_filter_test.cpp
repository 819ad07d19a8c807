// Filters against closed forms written out here independently of filters.cpp, and the filter
// sampler's offsets and weights against those closed forms, axis by axis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "penumbra/core/rng.h"
#include "penumbra/render/filter/filter.h"
#include "penumbra/render/filter/filter_sampler.h"

namespace penumbra {
namespace {

/// Gaussian of standard deviation sigma minus its value at the radius, zero outside (pbrt-v4's
/// GaussianFilter, as filters.h documents).
double gaussian_ref(double x, double radius, double sigma) {
  if (std::fabs(x) >= radius) return 0.0;
  const auto g = [sigma](double t) { return std::exp(-t * t / (2.0 * sigma * sigma)); };
  return std::max(0.0, g(x) - g(radius));
}

/// Mitchell and Netravali 1988, "Reconstruction Filters in Computer Graphics", equation (8):
/// k(x) = ((12 - 9B - 6C)|x|^3 + (-18 + 12B + 6C)|x|^2 + (6 - 2B)) / 6 for |x| < 1,
///        ((-B - 6C)|x|^3 + (6B + 30C)|x|^2 + (-12B - 48C)|x| + (8B + 24C)) / 6 for 1 <= |x| < 2,
/// written with the paper's coefficients P0..P3, Q0..Q3 and Horner's rule.
double mitchell_k(double x, double b, double c) {
  x = std::fabs(x);
  if (x >= 2.0) return 0.0;
  if (x < 1.0) {
    const double p0 = (6 - 2 * b) / 6, p2 = (-18 + 12 * b + 6 * c) / 6,
                 p3 = (12 - 9 * b - 6 * c) / 6;
    return p0 + x * x * (p2 + x * p3);
  }
  const double q0 = (8 * b + 24 * c) / 6, q1 = (-12 * b - 48 * c) / 6, q2 = (6 * b + 30 * c) / 6,
               q3 = (-b - 6 * c) / 6;
  return q0 + x * (q1 + x * (q2 + x * q3));
}

/// A float-rounding bound for evaluating the cubic above at x in single precision: a few ulps of
/// the sum of the magnitudes of its terms (the terms cancel in the outer lobe).
double mitchell_tolerance(double x, double b, double c) {
  x = std::fabs(x);
  const double ab = std::fabs(b), ac = std::fabs(c);
  const double terms =
      x < 1.0 ? (12 + 9 * ab + 6 * ac) * x * x * x + (18 + 12 * ab + 6 * ac) * x * x + (6 + 2 * ab)
              : (ab + 6 * ac) * x * x * x + (6 * ab + 30 * ac) * x * x + (12 * ab + 48 * ac) * x +
                    (8 * ab + 24 * ac);
  return 1e-7 + 16 * 6e-8 * terms / 6;
}

/// The cubic B-spline (Mitchell-Netravali B = 1, C = 0).
double cubic_bspline(double x) {
  x = std::fabs(x);
  if (x < 1) return (4 - 6 * x * x + 3 * x * x * x) / 6;
  if (x < 2) return (2 - x) * (2 - x) * (2 - x) / 6;
  return 0;
}

/// The Catmull-Rom spline (Mitchell-Netravali B = 0, C = 1/2).
double catmull_rom(double x) {
  x = std::fabs(x);
  if (x < 1) return 1.5 * x * x * x - 2.5 * x * x + 1;
  if (x < 2) return -0.5 * x * x * x + 2.5 * x * x - 4 * x + 2;
  return 0;
}

/// Evaluation points: a dense grid over [-radius - 0.5, radius + 0.5], plus the radius itself,
/// the cubic's knots and points just either side of them.
std::vector<double> eval_points(double radius) {
  std::vector<double> xs;
  const int n = 4001;
  for (int i = 0; i < n; ++i) xs.push_back(-(radius + 0.5) + (2 * radius + 1) * i / (n - 1));
  for (double k : {0.0, 0.5 * radius, radius})
    for (double s : {-1.0, 1.0})
      for (double e : {0.0, 1e-4, -1e-4}) xs.push_back(s * (k + e));
  return xs;
}

TEST(GapFilter, GaussianMatchesItsClosedForm) {
  struct Case {
    double radius, sigma;
  };
  for (const Case c : {Case{1.5, 0.5}, Case{2.0, 0.7}, Case{1.0, 0.3}, Case{3.0, 2.0}}) {
    const auto f = make_filter("gaussian:radius=" + std::to_string(c.radius) +
                               ",sigma=" + std::to_string(c.sigma));
    EXPECT_FLOAT_EQ(f->radius(), float(c.radius));
    for (double x : eval_points(c.radius)) {
      const double ref = gaussian_ref(float(x), c.radius, c.sigma);
      // exp in single precision and the subtraction of the offset: a few ulps of 1.
      EXPECT_NEAR(f->eval(float(x)), ref, 1e-6)
          << "x = " << x << ", radius " << c.radius << ", sigma " << c.sigma;
    }
    // The peak is 1 minus the offset; the filter vanishes at and beyond the radius.
    EXPECT_NEAR(f->eval(0.0f), 1.0 - std::exp(-c.radius * c.radius / (2 * c.sigma * c.sigma)),
                1e-6);
    EXPECT_EQ(f->eval(float(c.radius)), 0.0f);
    EXPECT_EQ(f->eval(-float(c.radius)), 0.0f);
  }
  // The defaults (radius 1.5, sigma 0.5).
  const auto def = make_filter("gaussian");
  EXPECT_FLOAT_EQ(def->radius(), 1.5f);
  for (double x : eval_points(1.5))
    EXPECT_NEAR(def->eval(float(x)), gaussian_ref(float(x), 1.5, 0.5), 1e-6);
}

TEST(GapFilter, MitchellMatchesItsClosedFormAtEveryRadius) {
  struct Case {
    double b, c, radius;
  };
  for (const Case c : {Case{1.0 / 3, 1.0 / 3, 2.0}, Case{0.0, 0.5, 2.0}, Case{1.0, 0.0, 2.0},
                       Case{0.5, 0.25, 1.5}, Case{0.2, 0.7, 3.0}, Case{-0.5, 1.2, 1.0}}) {
    const auto f = make_filter("mitchell:b=" + std::to_string(c.b) + ",c=" + std::to_string(c.c) +
                               ",radius=" + std::to_string(c.radius));
    EXPECT_FLOAT_EQ(f->radius(), float(c.radius));
    const double b = float(c.b), cc = float(c.c);  // the parameters as the filter holds them
    for (double x : eval_points(c.radius)) {
      // The support [-radius, radius] maps onto the cubic's [-2, 2].
      const double s = 2.0 * double(float(x)) / c.radius;
      EXPECT_NEAR(f->eval(float(x)), mitchell_k(s, b, cc), mitchell_tolerance(s, b, cc))
          << "x = " << x << ", b " << c.b << ", c " << c.c << ", radius " << c.radius;
    }
  }
  // The defaults (b = c = 1/3, radius 2).
  const auto def = make_filter("mitchell");
  EXPECT_FLOAT_EQ(def->radius(), 2.0f);
  for (double x : eval_points(2.0))
    EXPECT_NEAR(def->eval(float(x)), mitchell_k(float(x), 1.0 / 3, 1.0 / 3),
                mitchell_tolerance(x, 1.0 / 3, 1.0 / 3));
}

// Two members of the family have closed forms of their own: B = 1, C = 0 is the cubic B-spline
// and B = 0, C = 1/2 the Catmull-Rom spline.
TEST(GapFilter, MitchellFamilyContainsTheBSplineAndCatmullRom) {
  const auto bspline = make_filter("mitchell:b=1,c=0");
  const auto cr = make_filter("mitchell:b=0,c=0.5");
  const auto cr3 = make_filter("mitchell:b=0,c=0.5,radius=3");
  for (double x : eval_points(3.0)) {
    EXPECT_NEAR(bspline->eval(float(x)), cubic_bspline(float(x)), 2e-6) << "x = " << x;
    EXPECT_NEAR(cr->eval(float(x)), catmull_rom(float(x)), 2e-6) << "x = " << x;
    EXPECT_NEAR(cr3->eval(float(x)), catmull_rom(2.0 * float(x) / 3.0), 2e-6) << "x = " << x;
  }
}

// Every member of the family reproduces a constant: sum over integers k of k(x - k) = 1 (the
// condition Mitchell and Netravali impose; it is what makes the filter preserve flat fields).
// At radius 2 the filter is k itself.
TEST(GapFilter, MitchellIsAPartitionOfUnity) {
  for (const auto& [b, c] : std::vector<std::pair<double, double>>{
           {1.0 / 3, 1.0 / 3}, {0.0, 0.5}, {1.0, 0.0}, {0.3, 0.9}, {-0.5, 1.2}}) {
    const auto f =
        make_filter("mitchell:b=" + std::to_string(b) + ",c=" + std::to_string(c) + ",radius=2");
    for (int i = 0; i <= 200; ++i) {
      const double x = i / 200.0;
      double sum = 0;
      for (int k = -3; k <= 3; ++k) sum += f->eval(float(x - k));
      EXPECT_NEAR(sum, 1.0, 1e-5 * (1 + std::fabs(b) + std::fabs(c)))
          << "x = " << x << ", b " << b << ", c " << c;
    }
  }
}

/// A filter's closed form with a fine table of the CDF of |f| on [-radius, radius], for the
/// expected bin probabilities and quantiles of the sampler's offsets.
struct Reference {
  std::function<double(double)> f;
  double radius;
  std::vector<double> cdf;  ///< at kCells + 1 equally spaced nodes, normalised
  double abs_integral = 0, signed_integral = 0;
  static constexpr int kCells = 200000;

  Reference(std::function<double(double)> fn, double r) : f(std::move(fn)), radius(r) {
    cdf.assign(kCells + 1, 0.0);
    const double h = 2 * radius / kCells;
    for (int i = 0; i < kCells; ++i) {
      // Simpson's rule on each cell (|f| is smooth within a cell except at a zero crossing).
      const double x0 = -radius + h * i;
      const double v0 = f(x0), vm = f(x0 + h / 2), v1 = f(x0 + h);
      abs_integral += h * (std::fabs(v0) + 4 * std::fabs(vm) + std::fabs(v1)) / 6;
      signed_integral += h * (v0 + 4 * vm + v1) / 6;
      cdf[size_t(i) + 1] = abs_integral;
    }
    for (double& c : cdf) c /= abs_integral;
  }
  /// P(offset < x) under the density |f| / integral |f|.
  double cdf_at(double x) const {
    const double s = std::clamp((x + radius) / (2 * radius) * kCells, 0.0, double(kCells));
    const int i = std::min(int(s), kCells - 1);
    return cdf[size_t(i)] + (s - i) * (cdf[size_t(i) + 1] - cdf[size_t(i)]);
  }
  /// The p-quantile of |f| / integral |f|.
  double quantile(double p) const {
    const auto it = std::lower_bound(cdf.begin(), cdf.end(), p);
    const int i = std::clamp(int(it - cdf.begin()) - 1, 0, kCells - 1);
    const double d = cdf[size_t(i) + 1] - cdf[size_t(i)];
    const double t = d > 0 ? (p - cdf[size_t(i)]) / d : 0.5;
    return -radius + 2 * radius * (i + t) / kCells;
  }
};

struct SamplerCase {
  std::string spec;
  Reference ref;
};

std::vector<SamplerCase> sampler_cases() {
  std::vector<SamplerCase> cases;
  cases.push_back({"gaussian", Reference([](double x) { return gaussian_ref(x, 1.5, 0.5); }, 1.5)});
  cases.push_back({"gaussian:radius=2.5,sigma=0.8",
                   Reference([](double x) { return gaussian_ref(x, 2.5, 0.8); }, 2.5)});
  cases.push_back(
      {"mitchell", Reference([](double x) { return mitchell_k(x, 1.0 / 3, 1.0 / 3); }, 2.0)});
  // Strong negative lobes, and a radius that is not the cubic's own.
  cases.push_back({"mitchell:b=0,c=1,radius=1.5",
                   Reference([](double x) { return mitchell_k(2 * x / 1.5, 0.0, 1.0); }, 1.5)});
  return cases;
}

// The sampler inverts the CDF of |f| in each axis: offset.x is the u.x-quantile and offset.y the
// u.y-quantile of |f| / integral |f|, whatever the other coordinate. Its table is the 256-cell
// piecewise-linear interpolant of f, whose CDF differs from the exact one by less than 2e-4.
TEST(GapFilterSampler, EachAxisIsTheInverseCdfOfItsOwnUniform) {
  for (const SamplerCase& c : sampler_cases()) {
    const auto f = make_filter(c.spec);
    const FilterSampler fs(*f);
    for (int i = 1; i < 100; ++i) {
      const float u = float(i) / 100.0f;
      for (const float other : {0.03f, 0.5f, 0.91f}) {
        const FilterSample sx = fs.sample({u, other});
        const FilterSample sy = fs.sample({other, u});
        EXPECT_NEAR(c.ref.cdf_at(sx.offset.x), u, 2e-4) << c.spec << " x, u = " << u;
        EXPECT_NEAR(c.ref.cdf_at(sy.offset.y), u, 2e-4) << c.spec << " y, u = " << u;
        // The other axis depends on the other uniform only.
        EXPECT_EQ(sx.offset.y, fs.sample({0.5f, other}).offset.y) << c.spec;
        EXPECT_EQ(sy.offset.x, fs.sample({other, 0.5f}).offset.x) << c.spec;
      }
      EXPECT_LE(std::fabs(fs.sample({u, u}).offset.x), f->radius());
    }
    // Lower-left uniforms give lower-left offsets (no axis flipped).
    const FilterSample lo = fs.sample({0.1f, 0.2f});
    EXPECT_LT(lo.offset.x, 0.0f) << c.spec;
    EXPECT_LT(lo.offset.y, 0.0f) << c.spec;
    EXPECT_LT(lo.offset.x, lo.offset.y) << c.spec;
    const FilterSample hi = fs.sample({0.8f, 0.95f});
    EXPECT_GT(hi.offset.x, 0.0f) << c.spec;
    EXPECT_LT(hi.offset.x, hi.offset.y) << c.spec;
  }
}

// Chi-square of the x offsets and of the y offsets, separately, against |f|: 200,000 samples,
// 40 bins of equal expected probability 1/40 (edges at the quantiles of the closed form): 39
// degrees of freedom, whose chi-square quantile at significance 1e-4 is 80.65. Then the joint
// (x, y) in 8 x 8 cells of probability 1/64 each (the product of the marginals): 63 degrees of
// freedom, quantile 113.5.
TEST(GapFilterSampler, OffsetsFollowAbsFilterInEachAxisAndJointly) {
  const int n = 200000, bins = 40, jbins = 8;
  for (const SamplerCase& c : sampler_cases()) {
    const auto f = make_filter(c.spec);
    const FilterSampler fs(*f);
    std::vector<double> edges, jedges;
    for (int b = 1; b < bins; ++b) edges.push_back(c.ref.quantile(double(b) / bins));
    for (int b = 1; b < jbins; ++b) jedges.push_back(c.ref.quantile(double(b) / jbins));
    const auto bin_of = [](const std::vector<double>& e, float x) {
      return int(std::upper_bound(e.begin(), e.end(), double(x)) - e.begin());
    };
    std::vector<int> cx(bins, 0), cy(bins, 0), cj(jbins * jbins, 0);
    Pcg32 rng(20240611);
    for (int i = 0; i < n; ++i) {
      const float u0 = rng.next_float(), u1 = rng.next_float();
      const FilterSample s = fs.sample({u0, u1});
      ++cx[size_t(bin_of(edges, s.offset.x))];
      ++cy[size_t(bin_of(edges, s.offset.y))];
      ++cj[size_t(bin_of(jedges, s.offset.x) * jbins + bin_of(jedges, s.offset.y))];
    }
    const auto chi2 = [](const std::vector<int>& count, double expected) {
      double sum = 0;
      for (int k : count) sum += (k - expected) * (k - expected) / expected;
      return sum;
    };
    EXPECT_LT(chi2(cx, double(n) / bins), 80.65) << c.spec << " x offsets";
    EXPECT_LT(chi2(cy, double(n) / bins), 80.65) << c.spec << " y offsets";
    EXPECT_LT(chi2(cj, double(n) / (jbins * jbins)), 113.5) << c.spec << " joint offsets";
  }
}

/// Integrals of |f~| and f~ for the piecewise-linear interpolant f~ of the closed form at the
/// `cells` + 1 equally spaced nodes of [-radius, radius] (the trapezoid rule), the filter that
/// FilterSampler documents it represents.
std::pair<double, double> interpolant_integrals(const Reference& ref, int cells) {
  const double h = 2 * ref.radius / cells;
  double abs_sum = 0, sum = 0;
  for (int i = 0; i < cells; ++i) {
    const double f0 = ref.f(-ref.radius + h * i), f1 = ref.f(-ref.radius + h * (i + 1));
    abs_sum += h * (std::fabs(f0) + std::fabs(f1)) / 2;
    sum += h * (f0 + f1) / 2;
  }
  return {abs_sum, sum};
}

// The weight is f~(x) f~(y) / pdf(x, y) = sign(f~(x)) sign(f~(y)) (integral |f~|)^2 for the
// piecewise-linear f~ (256 cells) the sampler represents: check its sign sample by sample against
// the closed form in both axes (away from zero crossings, where the interpolant's sign may differ
// within one table cell), its magnitude, and that the mean weight estimates (integral f~)^2, the
// integral of the 2D filter, to within 5 standard errors.
TEST(GapFilterSampler, WeightsCarryTheSignsOfBothAxesAndIntegrateTheFilter) {
  const int n = 1000000;
  for (const SamplerCase& c : sampler_cases()) {
    const auto f = make_filter(c.spec);
    const FilterSampler fs(*f);
    const double cell = 2 * c.ref.radius / 256;
    const auto [abs_integral, signed_integral] = interpolant_integrals(c.ref, 256);
    // The sampler's table matches the closed form's to within the trapezoid rule's error.
    ASSERT_NEAR(abs_integral, c.ref.abs_integral, 1e-3 * c.ref.abs_integral) << c.spec;
    const double mag = abs_integral * abs_integral;
    const auto sign_of = [&](double x) {
      const double lo = c.ref.f(x - 1.5 * cell), mid = c.ref.f(x), hi = c.ref.f(x + 1.5 * cell);
      if ((lo < 0) != (mid < 0) || (hi < 0) != (mid < 0) || mid == 0) return 0;  // ambiguous
      return mid < 0 ? -1 : 1;
    };
    Pcg32 rng(7);
    double sum = 0;
    int negative = 0, checked = 0;
    for (int i = 0; i < n; ++i) {
      const float u0 = rng.next_float(), u1 = rng.next_float();
      const FilterSample s = fs.sample({u0, u1});
      sum += s.weight;
      if (s.weight < 0) ++negative;
      // Single-precision sums of 256 table cells: well within 1e-5 (relative).
      ASSERT_NEAR(std::fabs(s.weight), mag, 1e-5 * mag) << c.spec;
      if (i % 10 != 0) continue;
      const int sx = sign_of(s.offset.x), sy = sign_of(s.offset.y);
      if (sx == 0 || sy == 0) continue;
      ++checked;
      ASSERT_EQ(s.weight < 0, sx * sy < 0)
          << c.spec << " offset (" << s.offset.x << ", " << s.offset.y << ")";
    }
    EXPECT_GT(checked, n / 20);
    // Weights are +-mag: mean m = mag (1 - 2 p_neg), standard deviation mag sqrt(1 - (m/mag)^2).
    const double target = signed_integral * signed_integral;
    const double rel = target / mag;
    const double se = mag * std::sqrt(std::max(0.0, 1 - rel * rel) / n);
    EXPECT_NEAR(sum / n, target, 5 * se + 1e-5 * mag) << c.spec;
    if (c.spec.rfind("mitchell", 0) == 0) {
      EXPECT_GT(negative, n / 100) << c.spec;
    } else {
      EXPECT_EQ(negative, 0) << c.spec;
    }
  }
}

}  // namespace
}  // namespace penumbra
