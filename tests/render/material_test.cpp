#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/core/rng.h"
#include "penumbra/render/material/dielectric_material.h"
#include "penumbra/render/material/diffuse_material.h"

namespace penumbra {
namespace {

TEST(Fresnel, NormalIncidenceAndTotalInternalReflection) {
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);   // ((n-1)/(n+1))^2
  EXPECT_NEAR(fresnel_dielectric(-1.0f, 1.5f), 0.04f, 1e-6f);  // same from inside
  EXPECT_FLOAT_EQ(fresnel_dielectric(1.0f, 1.0f), 0.0f);       // index-matched: no reflection
  // From inside glass beyond the critical angle asin(1/1.5) = 41.8 deg: total reflection.
  EXPECT_FLOAT_EQ(fresnel_dielectric(-std::cos(0.8f), 1.5f), 1.0f);
  EXPECT_LT(fresnel_dielectric(-std::cos(0.7f), 1.5f), 1.0f);
  EXPECT_NEAR(fresnel_dielectric(0.0f, 1.5f), 1.0f, 1e-6f);  // grazing
}

TEST(Refract, ObeysSnellsLaw) {
  Pcg32 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const float ct = 0.05f + 0.95f * rng.next_float(), st = std::sqrt(1 - ct * ct);
    const Vec3 wo{st, 0, ct};
    Vec3 wi;
    float eta_rel;
    ASSERT_TRUE(refract(wo, 1.5f, wi, eta_rel));
    EXPECT_NEAR(length(wi), 1.0f, 1e-5f);
    EXPECT_LT(wi.z, 0.0f);
    const float st_t = std::sqrt(wi.x * wi.x + wi.y * wi.y);
    EXPECT_NEAR(st, 1.5f * st_t, 1e-5f);
    EXPECT_LT(wi.x, 0.0f);  // continues to the other side of the normal
  }
}

TEST(DielectricMaterial, LobesConserveEnergyAtTheInterface) {
  const DielectricMaterial glass(1.5f, Rgb(1.0f));
  for (float ct : {1.0f, 0.7f, 0.3f, 0.05f}) {
    const Vec3 wo{std::sqrt(1 - ct * ct), 0, ct};
    SpecularLobe lobes[2];
    ASSERT_EQ(glass.specular_lobes(wo, lobes), 2);
    // Reflected plus transmitted power is one: the transmitted radiance weight carries 1/eta^2.
    EXPECT_NEAR(lobes[0].weight.r + lobes[1].weight.r * 1.5f * 1.5f, 1.0f, 1e-5f);
  }
  // Total internal reflection from inside: a single lobe of weight one.
  SpecularLobe lobes[2];
  ASSERT_EQ(glass.specular_lobes({std::sin(1.0f), 0, -std::cos(1.0f)}, lobes), 1);
  EXPECT_FLOAT_EQ(lobes[0].weight.g, 1.0f);
}

// A cosine-sampled Lambertian estimate of its own albedo (f cos / pdf) is exact per sample.
TEST(DiffuseMaterial, SamplingIsConsistentWithEvalAndPdf) {
  const DiffuseMaterial m(Rgb(0.6f, 0.4f, 0.2f));
  Pcg32 rng(3);
  const Vec3 wo = normalize(Vec3{0.3f, -0.2f, 0.9f});
  for (int i = 0; i < 1000; ++i) {
    const auto s = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
    if (!s) continue;
    EXPECT_GT(s->wi.z, 0.0f);
    EXPECT_NEAR(s->pdf, m.pdf(wo, s->wi), 1e-6f);
    const Rgb est = s->f * (s->wi.z / s->pdf);
    EXPECT_NEAR(est.r, 0.6f, 1e-5f);
  }
  EXPECT_TRUE(m.eval(wo, {0, 0, -1}).is_black());  // no transmission
}

}  // namespace
}  // namespace penumbra
