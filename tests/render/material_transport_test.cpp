/// Tests of the materials' transport interface (TransportMode, lobe flags, relative eta): the
/// smooth dielectric's refraction from both sides in both modes, the rough dielectric's energy and
/// density against an independent quadrature of eval and pdf, the adjoint relation between
/// importance and radiance (Veach 1997, "Robust Monte Carlo Methods for Light Transport
/// Simulation", section 5.2), and the agreement of every material's flags with its samples'.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/core/rng.h"
#include "penumbra/render/material/conductor_material.h"
#include "penumbra/render/material/dielectric_material.h"
#include "penumbra/render/material/diffuse_material.h"
#include "penumbra/render/material/material_registry.h"
#include "penumbra/render/material/mirror_material.h"
#include "penumbra/render/material/rough_dielectric_material.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kSigmas = 4;  // statistical bounds at 4 standard errors (two-sided p ~ 6e-5)
constexpr TransportMode kModes[2] = {TransportMode::kRadiance, TransportMode::kImportance};

const char* mode_name(TransportMode mode) {
  return mode == TransportMode::kRadiance ? "radiance" : "importance";
}

// The unit local direction at polar angle theta_deg (degrees; above 90 is inside) and azimuth phi.
Vec3 direction(double theta_deg, double phi) {
  const double t = theta_deg * kPi / 180;
  return normalize(Vec3{float(std::sin(t) * std::cos(phi)), float(std::sin(t) * std::sin(phi)),
                        float(std::cos(t))});
}

// Uniform random direction on the sphere.
Vec3 random_direction(Pcg32& rng) {
  const double z = 1 - 2 * rng.next_double(), phi = 2 * kPi * rng.next_double();
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  return normalize(Vec3{float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)});
}

// |a - b| relative to the larger.
float relative_difference(float a, float b) {
  return std::fabs(a - b) / std::max({std::fabs(a), std::fabs(b), 1e-30f});
}

// The sample drawn with the next three numbers of rng (drawn in a fixed order).
std::optional<BsdfSample> draw(const Material& m, Vec3 wo, Pcg32& rng, TransportMode mode) {
  const float uc = rng.next_float(), u0 = rng.next_float(), u1 = rng.next_float();
  return m.sample(wo, uc, {u0, u1}, mode);
}

// The relative index n(wi's side) / n(wo's side) of a refraction of wo through an interface with
// index `ior` inside (z < 0) relative to outside.
double refraction_eta(Vec3 wo, double ior) {
  return wo.z > 0 ? ior : 1 / ior;
}

// Fresnel reflectance of unpolarised light arriving along -wo (cosine cos_o with the normal) at an
// interface of index `ior` inside relative to outside, in double precision and in the indices n1
// (wo's side) and n2 rather than their ratio (Hecht, "Optics", section 4.6); 1 under total
// internal reflection.
double fresnel_reference(double cos_o, double ior) {
  const double n1 = cos_o > 0 ? 1.0 : ior, n2 = cos_o > 0 ? ior : 1.0;
  const double c1 = std::fabs(cos_o), s2 = n1 / n2 * std::sqrt(std::max(0.0, 1 - c1 * c1));
  if (s2 >= 1) return 1;
  const double c2 = std::sqrt(1 - s2 * s2);
  const double rs = (n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2);
  const double rp = (n2 * c1 - n1 * c2) / (n2 * c1 + n1 * c2);
  return 0.5 * (rs * rs + rp * rp);
}

// The smooth interface as the two materials that offer it: DielectricMaterial and
// RoughDielectricMaterial at roughness 0 (which delegates to it).
struct SmoothCase {
  std::unique_ptr<Material> m;
  const char* name;
  float ior;
};

std::vector<SmoothCase> smooth_interfaces(Rgb tint) {
  std::vector<SmoothCase> all;
  for (float ior : {1.5f, 1.33f, 2.4f, 0.75f}) {
    all.push_back({std::make_unique<DielectricMaterial>(ior, tint), "dielectric", ior});
    all.push_back(
        {std::make_unique<RoughDielectricMaterial>(ior, 0.0f, tint), "rough_dielectric(0)", ior});
  }
  return all;
}

// Incident angles from outside (< 90 deg) and inside (> 90): for ior 1.5 the critical angle inside
// is 41.8 deg (theta 138.2), so 125 and 100 reflect totally; for ior 0.75 total reflection happens
// outside beyond 48.6 deg (70, 85). No angle lies within 3 deg of a critical one.
constexpr double kSmoothThetas[] = {0, 20, 45, 70, 85, 180, 160, 140, 125, 100};

// The weight of a sampled direction, f |cos i| / pdf: the factor a path's throughput takes.
Rgb throughput(const BsdfSample& s) {
  return s.f * (std::fabs(s.wi.z) / s.pdf);
}

// A smooth dielectric picks reflection with probability F and refraction with 1 - F. The delta
// BSDF is F delta_R / |cos| + tint (1 - F) / eta^2 delta_T / |cos| for radiance (no 1/eta^2 for
// importance), eta = n(wi's side) / n(wo's side): 1/ior from inside, ior from outside. So the lobe
// weight f |cos| of the refraction is tint (1 - F) / eta^2 (from inside the factor 1/eta^2 = ior^2
// > 1: radiance is compressed into the glass), its pdf 1 - F, and the throughput f |cos| / pdf that
// a path takes is tint / eta^2; the reflection's lobe weight is F, its pdf F, its throughput 1.
// Beyond the critical angle there is one lobe, reflection with weight 1.
TEST(MaterialTransport, SmoothDielectricRefractsWithTheRightWeightFromBothSides) {
  const Rgb tint(0.9f, 0.6f, 0.3f);
  int inside_refractions = 0, total_reflections = 0;
  for (const SmoothCase& c : smooth_interfaces(tint))
    for (double theta : kSmoothThetas) {
      const Vec3 wo = direction(theta, 0.7);
      SCOPED_TRACE(std::string(c.name) + " ior " + std::to_string(c.ior) + " theta " +
                   std::to_string(theta));
      const double fr = fresnel_reference(wo.z, c.ior), eta = refraction_eta(wo, c.ior);
      ASSERT_NEAR(fresnel_dielectric(wo.z, c.ior), fr, 1e-5);
      const bool total = std::sqrt(1 - double(wo.z) * wo.z) / eta >= 1;
      SpecularLobe lobes[2];
      ASSERT_EQ(c.m->specular_lobes(wo, lobes), total ? 1 : 2);
      const Vec3 mirror{-wo.x, -wo.y, wo.z};

      if (total) {
        // Total internal reflection: whatever uc, a reflection of weight one, untinted.
        ++total_reflections;
        EXPECT_NEAR(fr, 1.0, 1e-12);
        EXPECT_NEAR(lobes[0].weight.g, 1.0f, 1e-6f);
        for (TransportMode mode : kModes)
          for (float uc : {0.0f, 0.3f, 0.999f}) {
            const auto s = c.m->sample(wo, uc, {0.5f, 0.5f}, mode);
            ASSERT_TRUE(s.has_value());
            EXPECT_EQ(s->flags, kBsdfSpecular | kBsdfReflection);
            EXPECT_EQ(s->eta, 1.0f);
            EXPECT_NEAR(s->pdf, 1.0f, 1e-6f);
            EXPECT_NEAR(length(s->wi - mirror), 0.0f, 1e-6f);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(throughput(*s)[k], 1.0f, 1e-5f);
          }
        continue;
      }

      for (TransportMode mode : kModes) {
        SCOPED_TRACE(mode_name(mode));
        const double scale = mode == TransportMode::kRadiance ? 1 / (eta * eta) : 1.0;
        // Refraction: any uc at or above F.
        const auto t = c.m->sample(wo, 0.5f * (1.0f + float(fr)), {0.5f, 0.5f}, mode);
        ASSERT_TRUE(t.has_value());
        EXPECT_EQ(t->flags, kBsdfSpecular | kBsdfTransmission);
        EXPECT_TRUE(t->is_specular());
        EXPECT_TRUE(t->is_transmission());
        EXPECT_FLOAT_EQ(t->eta, float(eta));
        EXPECT_NEAR(t->pdf, 1 - fr, 1e-5);
        // Snell's law n_o sin_o = n_i sin_i, in the plane of incidence, on the other side.
        EXPECT_NEAR(length(t->wi), 1.0f, 1e-5f);
        EXPECT_LT(t->wi.z * wo.z, 0.0f);
        const double sin_o = std::hypot(wo.x, wo.y), sin_i = std::hypot(t->wi.x, t->wi.y);
        EXPECT_NEAR(sin_o, eta * sin_i, 1e-5);
        EXPECT_NEAR(cross(wo, t->wi).z, 0.0f, 1e-6f);
        EXPECT_LE(wo.x * t->wi.x + wo.y * t->wi.y, 1e-7f);
        EXPECT_NEAR(length(t->wi - lobes[1].wi), 0.0f, 1e-6f);
        for (int k = 0; k < 3; ++k) {
          const double lobe_weight = t->f[k] * std::fabs(t->wi.z);
          EXPECT_NEAR(lobe_weight, tint[k] * (1 - fr) * scale, 1e-5 * tint[k] * scale);
          EXPECT_NEAR(throughput(*t)[k], tint[k] * scale, 1e-5 * tint[k] * scale);
          if (mode == TransportMode::kRadiance) {  // specular_lobes is weighted for radiance
            EXPECT_NEAR(lobes[1].weight[k], lobe_weight, 1e-5 * tint[k] * scale);
          }
        }
        if (wo.z < 0 && mode == TransportMode::kRadiance) {
          // Leaving the inside, the factor 1/eta^2 = ior^2: above 1 for glass, below for ior < 1.
          ++inside_refractions;
          EXPECT_NEAR(throughput(*t).g / tint.g, double(c.ior) * c.ior, 1e-5 * c.ior * c.ior);
          if (c.ior > 1) {
            EXPECT_GT(throughput(*t).g, tint.g);
          }
        }
        // Reflection: any uc below F; the same in both modes.
        const auto r = c.m->sample(wo, 0.5f * float(fr), {0.5f, 0.5f}, mode);
        ASSERT_TRUE(r.has_value());
        EXPECT_EQ(r->flags, kBsdfSpecular | kBsdfReflection);
        EXPECT_FALSE(r->is_transmission());
        EXPECT_EQ(r->eta, 1.0f);
        EXPECT_NEAR(r->pdf, fr, 1e-5);
        EXPECT_NEAR(length(r->wi - mirror), 0.0f, 1e-6f);
        for (int k = 0; k < 3; ++k) {
          EXPECT_NEAR(r->f[k] * std::fabs(r->wi.z), fr, 1e-5);  // untinted
          EXPECT_NEAR(throughput(*r)[k], 1.0f, 1e-5f);
        }
        EXPECT_NEAR(lobes[0].weight.g, fr, 1e-5);
      }
    }
  // Per material, refraction from inside at 3 + 3 + 2 + 5 angles (ior 1.5, 1.33, 2.4, 0.75) and
  // total reflection at 2 + 2 + 3 + 2: both branches were exercised.
  EXPECT_EQ(inside_refractions, 2 * 13);
  EXPECT_EQ(total_reflections, 2 * 9);
}

// Over uniform uc, a smooth dielectric reflects with frequency fresnel_dielectric(cos, ior), and
// the mean throughput f |cos| / pdf is the sum of the lobe weights that specular_lobes (the
// deterministic form used by distribution ray tracing) reports, F + tint (1 - F) / eta^2: a path
// tracer that follows one sampled lobe is unbiased. A sample that returned the lobe weight as its
// throughput would give F^2 + tint (1 - F)^2 / eta^2 instead.
TEST(MaterialTransport, SmoothDielectricChoosesLobesByFresnelWithoutBias) {
  const Rgb tint(0.9f, 0.6f, 0.3f);
  constexpr int kN = 20000;
  for (const SmoothCase& c : smooth_interfaces(tint))
    for (double theta : kSmoothThetas) {
      const Vec3 wo = direction(theta, 0.3);
      SCOPED_TRACE(std::string(c.name) + " ior " + std::to_string(c.ior) + " theta " +
                   std::to_string(theta));
      SpecularLobe lobes[2];
      const int n = c.m->specular_lobes(wo, lobes);
      double expected = 0;
      for (int i = 0; i < n; ++i) expected += lobes[i].weight.b;
      const double fr = fresnel_dielectric(wo.z, c.ior);
      Pcg32 rng(101 + uint64_t(theta));
      double sum = 0, sum2 = 0;
      int reflections = 0;
      for (int i = 0; i < kN; ++i) {
        const auto s = draw(*c.m, wo, rng, TransportMode::kRadiance);
        ASSERT_TRUE(s.has_value());
        reflections += !s->is_transmission();
        const double w = throughput(*s).b;
        sum += w, sum2 += w * w;
      }
      const double p = double(reflections) / kN;
      EXPECT_NEAR(p, fr, kSigmas * std::sqrt(fr * (1 - fr) / kN) + 1e-6);
      const double mean = sum / kN, se = std::sqrt(std::max(0.0, sum2 / kN - mean * mean) / kN);
      EXPECT_NEAR(mean, expected, kSigmas * se + 1e-5);
    }
}

// Integrals over the sphere of wi of f(wo, wi) |cos i| (per mode, reflected and transmitted
// parts) and of pdf(wo, wi).
struct SphereIntegrals {
  double reflected[2] = {}, transmitted[2] = {}, pdf = 0;
  double albedo(int mode) const { return reflected[mode] + transmitted[mode]; }
};

// The integrals by the midpoint rule on an n x n grid in (theta in [0, pi], phi in [0, pi]) with
// the area element sin(theta) dtheta dphi, doubled by the mirror symmetry y -> -y of an isotropic
// material (wo must lie in the xz plane). Only eval and pdf are called: the rule is independent
// of sample().
SphereIntegrals integrate_sphere(const Material& m, Vec3 wo, int n) {
  SphereIntegrals q;
  const double step = kPi / n;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) * step, st = std::sin(theta), ct = std::cos(theta);
    const double area = 2 * st * step * step;
    for (int j = 0; j < n; ++j) {
      const double phi = (j + 0.5) * step;
      const Vec3 wi =
          normalize(Vec3{float(st * std::cos(phi)), float(st * std::sin(phi)), float(ct)});
      const double weight = area * std::fabs(wi.z);
      const bool reflect = same_hemisphere(wo, wi);
      for (int k = 0; k < 2; ++k) {
        const double f = m.eval(wo, wi, kModes[k]).g * weight;
        (reflect ? q.reflected[k] : q.transmitted[k]) += f;
      }
      q.pdf += m.pdf(wo, wi) * area;
    }
  }
  return q;
}

// Mean and standard error of the throughput f |cos| / pdf of n samples from wo (rejected ones
// count as zero), the fraction accepted, and the largest relative differences between a sample's
// f and pdf and eval and pdf at its direction (except near grazing its microfacet).
struct MonteCarlo {
  double mean = 0, se = 0, accepted = 0;
  float worst_f = 0, worst_pdf = 0;
  int skipped = 0;  ///< samples near grazing their microfacet, not compared
};

MonteCarlo estimate_albedo(const Material& m, Vec3 wo, TransportMode mode, int n, uint64_t seed) {
  Pcg32 rng(seed);
  MonteCarlo e;
  double sum = 0, sum2 = 0;
  int accepted = 0;
  for (int i = 0; i < n; ++i) {
    const auto s = draw(m, wo, rng, mode);
    if (!s) continue;
    ++accepted;
    const double w = throughput(*s).g;
    sum += w, sum2 += w * w;
    // Skip directions within ~1 degree of grazing their microfacet (h parallel to n_o wo + n_i
    // wi): refracted there, near the critical angle, 1 - F and the Jacobian have infinite slope
    // and the rounding of wi alone changes f and pdf by up to 1e-2.
    const Vec3 h = normalize(wo + s->wi * s->eta);
    if (std::fabs(dot(wo, h)) < 0.02f || std::fabs(dot(s->wi, h)) < 0.02f) {
      ++e.skipped;
      continue;
    }
    e.worst_pdf = std::max(e.worst_pdf, relative_difference(s->pdf, m.pdf(wo, s->wi)));
    const Rgb f = m.eval(wo, s->wi, mode);
    for (int c = 0; c < 3; ++c) e.worst_f = std::max(e.worst_f, relative_difference(s->f[c], f[c]));
  }
  e.mean = sum / n;
  e.se = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / n);
  e.accepted = double(accepted) / n;
  return e;
}

// The rough dielectric's directional albedo, integral of f(wo, wi) |cos i| over the sphere, by the
// quadrature above (1024 x 1024 nodes; its error bounded by twice the change from 512 x 512, the
// rule's error falling at least linearly with the spacing, plus 2e-4) against the mean of f |cos|
// / pdf from sample(), within 4 standard errors plus that error, in both modes, from outside and
// inside, below and beyond the critical angle. Importance conserves energy (albedo <= 1); the
// radiance transmission is the importance one over eta^2. The density integrates to at most one:
// to the fraction of samples sample() accepts (the rest, directions on the wrong side, rejected).
// At every sample, eval and pdf agree with its f and pdf.
TEST(MaterialTransport, RoughDielectricEnergyMatchesQuadrature) {
  struct Case {
    float ior, roughness;
    double theta;
  };
  const Case cases[] = {
      {1.5f, 0.3f, 30}, {1.5f, 0.3f, 150}, {1.5f, 0.5f, 70},  {1.5f, 0.5f, 125},
      {1.33f, 1.0f, 0}, {2.4f, 0.5f, 160}, {0.75f, 0.4f, 60}, {1.5f, 0.7f, 100},
  };
  constexpr int kSamples = 200000;
  for (const Case& c : cases) {
    SCOPED_TRACE("ior " + std::to_string(c.ior) + " roughness " + std::to_string(c.roughness) +
                 " theta " + std::to_string(c.theta));
    const RoughDielectricMaterial m(c.ior, c.roughness, Rgb(1.0f));
    const Vec3 wo = direction(c.theta, 0.0);
    const SphereIntegrals fine = integrate_sphere(m, wo, 1024),
                          coarse = integrate_sphere(m, wo, 512);
    const double eta = refraction_eta(wo, c.ior);
    const double pdf_error = 2 * std::fabs(fine.pdf - coarse.pdf) + 2e-4;
    EXPECT_LE(fine.pdf, 1 + pdf_error);
    std::printf("rough_dielectric ior %.2f roughness %.1f theta %3.0f: pdf mass %.4f", c.ior,
                c.roughness, c.theta, fine.pdf);
    for (int k = 0; k < 2; ++k) {
      SCOPED_TRACE(mode_name(kModes[k]));
      const double error = 2 * std::fabs(fine.albedo(k) - coarse.albedo(k)) + 2e-4;
      const MonteCarlo e = estimate_albedo(m, wo, kModes[k], kSamples, 31 + 7 * k);
      std::printf("; %s albedo %.4f (R %.4f T %.4f) sampled %.4f +- %.4f accepted %.4f",
                  mode_name(kModes[k]), fine.albedo(k), fine.reflected[k], fine.transmitted[k],
                  e.mean, e.se, e.accepted);
      EXPECT_NEAR(e.mean, fine.albedo(k), kSigmas * e.se + error);
      EXPECT_NEAR(e.accepted, fine.pdf,
                  kSigmas * std::sqrt(e.accepted * (1 - e.accepted) / kSamples) + pdf_error);
      EXPECT_LE(e.worst_f, 1e-3f);
      EXPECT_LE(e.worst_pdf, 1e-3f);
      EXPECT_LT(e.skipped, kSamples / 100);
      EXPECT_GT(fine.transmitted[k], 0.02);  // the transmission lobe was integrated
      if (kModes[k] == TransportMode::kImportance) {
        EXPECT_LE(fine.albedo(k), 1 + error);
      }
    }
    std::printf("\n");
    // Reflection is the same in both modes; transmission differs by 1/eta^2 for radiance.
    EXPECT_NEAR(fine.reflected[0], fine.reflected[1], 1e-6 * fine.reflected[1]);
    EXPECT_NEAR(fine.transmitted[0], fine.transmitted[1] / (eta * eta), 1e-5 * fine.transmitted[0]);
  }
}

// The importance BSDF is the adjoint of the radiance one: f_importance(wo, wi) = f_radiance(wi,
// wo) (Veach 1997, section 5.2), for pairs on opposite sides (refraction, where the two modes
// differ by eta^2) and on the same side (reflection, where they agree and the BSDF is reciprocal).
TEST(MaterialTransport, RoughDielectricImportanceIsTheAdjointOfRadiance) {
  Pcg32 rng(17);
  for (float ior : {1.5f, 0.8f, 2.4f})
    for (float roughness : {0.3f, 0.6f, 1.0f}) {
      SCOPED_TRACE("ior " + std::to_string(ior) + " roughness " + std::to_string(roughness));
      const RoughDielectricMaterial m(ior, roughness, Rgb(0.9f, 0.8f, 0.7f));
      int transmissions = 0, reflections = 0;
      for (int i = 0; i < 4000; ++i) {
        const Vec3 wo = random_direction(rng), wi = random_direction(rng);
        // Skip microfacets seen within ~1 degree of grazing from either side: there the Fresnel
        // factor's infinite slope at the critical angle turns the rounding of the two ways of
        // computing the half vector into relative differences up to 1e-2.
        const float n_o = wo.z > 0 ? 1.0f : ior, n_i = wi.z > 0 ? 1.0f : ior;
        const Vec3 h = normalize(wo * n_o + wi * n_i);
        if (std::fabs(dot(wo, h)) < 0.02f || std::fabs(dot(wi, h)) < 0.02f) continue;
        const Rgb importance = m.eval(wo, wi, TransportMode::kImportance);
        const Rgb adjoint = m.eval(wi, wo, TransportMode::kRadiance);
        const Rgb radiance = m.eval(wo, wi, TransportMode::kRadiance);
        if (importance.is_black()) continue;
        const bool reflect = same_hemisphere(wo, wi);
        // eta = n(wi's side) / n(wo's side): importance = radiance * eta^2.
        const float eta2 = reflect ? 1.0f : (n_i / n_o) * (n_i / n_o);
        for (int c = 0; c < 3; ++c) {
          ASSERT_LE(relative_difference(importance[c], adjoint[c]), 1e-3f)
              << (reflect ? "reflection " : "transmission ") << i;
          ASSERT_LE(relative_difference(importance[c], radiance[c] * eta2), 1e-5f) << i;
        }
        ++(reflect ? reflections : transmissions);
      }
      EXPECT_GT(transmissions, 100);
      EXPECT_GT(reflections, 100);
    }
}

// Reflection only (diffuse, conductors, mirror): the BSDF is symmetric, so eval and sample are
// the same, bit for bit, in both modes.
TEST(MaterialTransport, ReflectorsIgnoreTheTransportMode) {
  const auto gold =
      ConductorFresnel::complex_ior(Rgb(0.143f, 0.375f, 1.442f), Rgb(3.983f, 2.386f, 1.603f));
  std::vector<std::unique_ptr<Material>> all;
  all.push_back(std::make_unique<DiffuseMaterial>(Rgb(0.6f, 0.4f, 0.2f)));
  all.push_back(std::make_unique<MirrorMaterial>(Rgb(0.9f, 0.8f, 0.7f)));
  for (float roughness : {0.0f, 0.2f, 0.6f}) {
    all.push_back(std::make_unique<ConductorMaterial>(gold, roughness));
    all.push_back(std::make_unique<ConductorMaterial>(
        ConductorFresnel::schlick_f0(Rgb(0.9f, 0.6f, 0.3f)), roughness));
  }
  Pcg32 rng(23);
  for (size_t k = 0; k < all.size(); ++k) {
    const Material& m = *all[k];
    int non_black = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = random_direction(rng), wi = random_direction(rng);
      const Rgb radiance = m.eval(wo, wi, TransportMode::kRadiance);
      ASSERT_EQ(radiance, m.eval(wo, wi, TransportMode::kImportance)) << k;
      non_black += !radiance.is_black();
      const float uc = rng.next_float(), u0 = rng.next_float(), u1 = rng.next_float();
      const auto a = m.sample(wo, uc, {u0, u1}, TransportMode::kRadiance);
      const auto b = m.sample(wo, uc, {u0, u1}, TransportMode::kImportance);
      ASSERT_EQ(a.has_value(), b.has_value()) << k;
      if (!a) continue;
      EXPECT_EQ(a->wi, b->wi);
      EXPECT_EQ(a->f, b->f);
      EXPECT_EQ(a->pdf, b->pdf);
      EXPECT_EQ(a->flags, b->flags);
      EXPECT_EQ(a->eta, b->eta);
    }
    EXPECT_EQ(non_black > 0, m.has_non_specular()) << k;
  }
}

// One material for the flags test, made through the registry from its scene description.
struct FlagsCase {
  const char* json;
  BsdfFlags flags;  ///< expected flags()
  float ior;        ///< index inside relative to outside, for transmitting materials
};

SceneParams params(const char* json_text) {
  return SceneParams(nlohmann::json::parse(json_text), "scene.json", "/materials/m");
}

// Every material's flags() names its lobes, and the samples it draws agree with them: exactly one
// side (reflection iff wi lies on wo's side) and one kind (diffuse, glossy or specular) per sample,
// both among the material's flags, every lobe of flags() drawn; eta = 1 for reflection and n(wi's
// side) / n(wo's side) != 1 for transmission; specular samples lie outside eval and pdf (and
// among specular_lobes' directions), others inside; has_non_specular(), is_glossy() and
// is_specular() follow from flags(). Each registered type must appear in the table.
TEST(MaterialTransport, FlagsOfMaterialsAndSamplesAgree) {
  const FlagsCase cases[] = {
      {R"({"type": "diffuse", "albedo": [0.6, 0.5, 0.4]})", kBsdfDiffuse | kBsdfReflection, 0},
      {R"({"type": "mirror"})", kBsdfSpecular | kBsdfReflection, 0},
      {R"({"type": "dielectric", "ior": 1.5})", kBsdfSpecular | kBsdfReflection | kBsdfTransmission,
       1.5f},
      {R"({"type": "dielectric", "ior": 0.8, "tint": [0.9, 0.8, 0.7]})",
       kBsdfSpecular | kBsdfReflection | kBsdfTransmission, 0.8f},
      {R"({"type": "conductor", "reflectance": [0.9, 0.8, 0.5], "roughness": 0.3})",
       kBsdfGlossy | kBsdfReflection, 0},
      {R"({"type": "conductor", "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1], "roughness": 0})",
       kBsdfSpecular | kBsdfReflection, 0},
      {R"({"type": "rough_dielectric", "ior": 1.5, "roughness": 0.3})",
       kBsdfGlossy | kBsdfReflection | kBsdfTransmission, 1.5f},
      {R"({"type": "rough_dielectric", "ior": 1.33, "roughness": 0})",
       kBsdfSpecular | kBsdfReflection | kBsdfTransmission, 1.33f},
      // Index-matched within 1e-3: a smooth interface, which still bends (eta != 1).
      {R"({"type": "rough_dielectric", "ior": 1.0005, "roughness": 0.5})",
       kBsdfSpecular | kBsdfReflection | kBsdfTransmission, 1.0005f},
  };
  for (const std::string& type : material_types()) {
    bool covered = false;
    for (const FlagsCase& c : cases) covered |= params(c.json).type() == type;
    EXPECT_TRUE(covered) << "material type '" << type << "' is missing from this test";
  }
  constexpr BsdfFlags kSides = kBsdfReflection | kBsdfTransmission;
  constexpr BsdfFlags kKinds = kBsdfDiffuse | kBsdfGlossy | kBsdfSpecular;
  Pcg32 rng(29);
  for (const FlagsCase& c : cases) {
    SCOPED_TRACE(c.json);
    const std::unique_ptr<Material> m = make_material(params(c.json));
    const BsdfFlags flags = m->flags();
    ASSERT_EQ(flags, c.flags);
    EXPECT_EQ(m->has_non_specular(), (flags & (kBsdfDiffuse | kBsdfGlossy)) != 0);
    EXPECT_EQ(m->is_glossy(), (flags & kBsdfGlossy) != 0);
    EXPECT_EQ(m->is_specular(), !m->has_non_specular());
    EXPECT_EQ(m->is_specular(), (flags & kKinds) == kBsdfSpecular);
    int seen = kBsdfNone, non_black_evals = 0;
    for (int i = 0; i < 400; ++i) {
      const Vec3 wo = random_direction(rng);
      SpecularLobe lobes[2];
      const int n_lobes = m->specular_lobes(wo, lobes);
      EXPECT_EQ(n_lobes > 0, (flags & kBsdfSpecular) != 0);
      non_black_evals += !m->eval(wo, random_direction(rng)).is_black();
      for (TransportMode mode : kModes)
        for (int j = 0; j < 4; ++j) {
          const auto s = draw(*m, wo, rng, mode);
          if (!s) continue;
          const int side = s->flags & kSides, kind = s->flags & kKinds;
          ASSERT_TRUE(side == kBsdfReflection || side == kBsdfTransmission) << int(s->flags);
          ASSERT_TRUE(kind == kBsdfDiffuse || kind == kBsdfGlossy || kind == kBsdfSpecular)
              << int(s->flags);
          ASSERT_EQ(s->flags & ~flags, 0) << "a lobe that flags() lacks: " << int(s->flags);
          seen |= s->flags;
          EXPECT_EQ(s->is_specular(), kind == kBsdfSpecular);
          EXPECT_EQ(s->is_transmission(), side == kBsdfTransmission);
          EXPECT_EQ(same_hemisphere(wo, s->wi), side == kBsdfReflection);
          if (side == kBsdfReflection) {
            EXPECT_EQ(s->eta, 1.0f);
          } else {
            EXPECT_NE(s->eta, 1.0f);
            EXPECT_FLOAT_EQ(s->eta, float(refraction_eta(wo, c.ior)));
          }
          if (s->is_specular()) {
            EXPECT_EQ(m->pdf(wo, s->wi), 0.0f);
            EXPECT_TRUE(m->eval(wo, s->wi, mode).is_black());
            float nearest = INFINITY;
            for (int l = 0; l < n_lobes; ++l)
              nearest = std::min(nearest, length(s->wi - lobes[l].wi));
            EXPECT_LE(nearest, 1e-6f);
          } else {
            EXPECT_GT(m->pdf(wo, s->wi), 0.0f);
            EXPECT_FALSE(m->eval(wo, s->wi, mode).is_black());
          }
        }
    }
    EXPECT_EQ(seen, int(flags)) << "lobes drawn: " << seen;
    EXPECT_EQ(non_black_evals > 0, m->has_non_specular());
  }
}

}  // namespace
}  // namespace penumbra
