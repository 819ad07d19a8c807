// The path tracer against truth: furnaces with exact answers, the three strategies against each
// other, MIS against its parts on Veach's scene, and the convergence rate.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "penumbra/render/render_job.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// A finished render: the pixel means and the variance of each mean.
struct Rendered {
  RgbImage mean, variance;
};

Rendered render_scene(const std::string& json) {
  RenderJob job(test::scene_from_text(json));
  job.run();
  return {job.film->resolve(), job.film->variance()};
}

/// Camera 3 units in front of a sphere of radius 1 (angular radius 19.5 degrees in a 40-degree
/// view), under a uniform environment of radiance 1.
std::string furnace_scene(float albedo, const std::string& integrator, int spp) {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 0, -3], "look_at": [0, 0, 0], "vfov": 40}},
    "render": {{"resolution": [16, 16], "spp": {}, "seed": 3, "integrator": "{}",
                "background": [1, 1, 1]}},
    "materials": {{"m": {{"type": "diffuse", "albedo": [{}, {}, {}]}}}},
    "shapes": [{{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}}]
  }})",
                     spp, integrator, albedo, albedo, albedo);
}

// White furnace: a convex diffuse sphere of albedo rho under a uniform environment of radiance 1
// receives radiance 1 from every direction, so it reflects exactly rho (rho = 1: it vanishes).
// The expected value of each pixel is the mixture of rho and 1 that its own sample positions
// cover, which the albedo view with the same sampler and seed gives exactly (the pixel position
// is the first sample dimension of both). Each pixel within 5 sigma of its sample variance (256
// pixels; the variance itself is estimated from 256 samples), the whole sphere's mean within 4
// sigma, both with a slack for float rounding (1e-6 per pixel: an exact path gives rho within a
// few ulps).
TEST(PathFurnace, DiffuseSphereUnderUniformSkyReflectsItsAlbedo) {
  for (const char* strategy : {"mis", "nee", "bsdf"}) {
    for (const float rho : {0.8f, 1.0f}) {
      SCOPED_TRACE(fmt::format("strategy {} rho {}", strategy, rho));
      const Rendered cover = render_scene(furnace_scene(rho, "raycast:mode=albedo", 256));
      const Rendered path =
          render_scene(furnace_scene(rho, fmt::format("path:strategy={}", strategy), 256));
      double sum_diff = 0, sum_var = 0;
      int sphere_pixels = 0;
      for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
          const float expected = cover.mean.at(x, y).g;
          const float got = path.mean.at(x, y).g;
          const float var = path.variance.at(x, y).g;
          EXPECT_LE(std::fabs(got - expected), 5.0f * std::sqrt(var) + 1e-6f)
              << "pixel " << x << "," << y;
          if (expected < 1.0f || rho == 1.0f) {
            sum_diff += got - expected;
            sum_var += var;
            ++sphere_pixels;
          }
        }
      ASSERT_GT(sphere_pixels, 20);
      EXPECT_LE(std::fabs(sum_diff), 4.0 * std::sqrt(sum_var) + 1e-6 * sphere_pixels);
    }
  }
}

// Inside a closed diffuse enclosure of uniform emission E and albedo rho, every point sees
// radiance L with L = E + rho L, so L = E / (1 - rho): here 0.5 / 0.4 = 1.25, the sum of
// unboundedly many bounces (Russian roulette ends the paths without bias). A sphere seen from
// inside (two-sided emission; NEE falls back to area sampling inside it) and a cube of six
// separate quad lights (solid-angle sampling of rectangles, the light sampler over six lights).
TEST(PathFurnace, ClosedEmissiveEnclosureReachesEOverOneMinusRho) {
  const std::string sphere = R"({"type": "sphere", "center": [0, 0, 0], "radius": 2,
      "material": "m", "emission": [0.5, 0.5, 0.5], "two_sided": true})";
  std::string cube;
  const char* faces[6][3] = {
      {"[-1, -1, -1]", "[2, 0, 0]", "[0, 2, 0]"}, {"[-1, -1, 1]", "[0, 2, 0]", "[2, 0, 0]"},
      {"[-1, -1, -1]", "[0, 0, 2]", "[2, 0, 0]"}, {"[-1, 1, -1]", "[2, 0, 0]", "[0, 0, 2]"},
      {"[-1, -1, -1]", "[0, 2, 0]", "[0, 0, 2]"}, {"[1, -1, -1]", "[0, 0, 2]", "[0, 2, 0]"}};
  for (const auto& f : faces)
    cube += fmt::format(R"({}{{"type": "quad", "origin": {}, "edge1": {}, "edge2": {},
        "material": "m", "emission": [0.5, 0.5, 0.5], "two_sided": true}})",
                        cube.empty() ? "" : ",", f[0], f[1], f[2]);
  for (const std::string& shapes : {sphere, cube}) {
    for (const char* strategy : {"mis", "nee", "bsdf"}) {
      SCOPED_TRACE(fmt::format("strategy {} shapes {}", strategy, shapes.substr(0, 20)));
      const Rendered r = render_scene(fmt::format(R"({{
        "camera": {{"type": "pinhole", "position": [0.1, 0.2, -0.3], "look_at": [0.5, 0, 1],
                    "vfov": 90}},
        "render": {{"resolution": [8, 8], "spp": 128, "seed": 5,
                    "integrator": "path:strategy={}"}},
        "materials": {{"m": {{"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}}}},
        "shapes": [{}]
      }})",
                                                  strategy, shapes));
      double sum = 0, var = 0;
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) sum += r.mean.at(x, y).r, var += r.variance.at(x, y).r;
      EXPECT_LE(std::fabs(sum / 64.0 - 1.25), 4.0 * std::sqrt(var) / 64.0);
      EXPECT_GT(var, 0.0);  // the estimate is noisy: the bounds mean something
      // Every 2x2 block (512 paths) against the pooled variance of the mean: the pixels see
      // statistically alike paths (their variances differ by under 30 %), while one pixel's
      // own variance estimate from 128 paths, whose Russian-roulette tails are heavy, is often
      // far too small where the rare long paths happened not to be drawn (measured over 40
      // seeds: |z| > 4 for 0.3 % of pixels by their own variance; 2x2 blocks by the pooled
      // variance: std(z) 0.99-1.02, max |z| 3.5 of 640).
      const double block_sigma = std::sqrt(var / 64.0 / 4.0);
      for (int y = 0; y < 8; y += 2)
        for (int x = 0; x < 8; x += 2) {
          const double l = (double(r.mean.at(x, y).r) + r.mean.at(x + 1, y).r +
                            r.mean.at(x, y + 1).r + r.mean.at(x + 1, y + 1).r) / 4.0;
          EXPECT_LE(std::fabs(l - 1.25), 4.5 * block_sigma) << "block " << x << "," << y;
        }
    }
  }
}

/// A small room: floor and back wall, a quad light, a rough metal sphere, a diffuse sphere and a
/// glass sphere (caustics through it count after the specular bounce in every strategy).
std::string room_scene(const std::string& strategy, int spp, int seed) {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 1.2, -4], "look_at": [0, 0.8, 0], "vfov": 45}},
    "render": {{"resolution": [24, 24], "spp": {}, "seed": {}, "integrator": "path:strategy={}"}},
    "materials": {{
      "white": {{"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
      "red": {{"type": "diffuse", "albedo": [0.7, 0.2, 0.1]}},
      "metal": {{"type": "conductor", "reflectance": [0.9, 0.8, 0.5], "roughness": 0.35}},
      "glass": {{"type": "dielectric", "ior": 1.5}}
    }},
    "shapes": [
      {{"type": "quad", "origin": [-3, 0, -3], "edge1": [0, 0, 6], "edge2": [6, 0, 0],
        "material": "white"}},
      {{"type": "quad", "origin": [-3, 0, 2], "edge1": [6, 0, 0], "edge2": [0, 4, 0],
        "material": "red"}},
      {{"type": "quad", "origin": [-0.6, 2.6, -0.6], "edge1": [1.2, 0, 0], "edge2": [0, 0, 1.2],
        "material": "white", "emission": [6, 6, 6]}},
      {{"type": "sphere", "center": [-1.1, 0.6, 0.3], "radius": 0.6, "material": "metal"}},
      {{"type": "sphere", "center": [0.2, 0.5, -0.6], "radius": 0.5, "material": "glass"}},
      {{"type": "sphere", "center": [1.2, 0.5, 0.5], "radius": 0.5, "material": "white"}}
    ]
  }})",
                     spp, seed, strategy);
}

// nee, bsdf and mis estimate the same integral: on every 4 x 4 block of pixels and channel,
// each pair of strategies agrees within 4.5 standard errors of the difference.
TEST(PathStrategies, MisNeeAndBsdfAgreeOnEveryRegion) {
  const char* names[3] = {"mis", "nee", "bsdf"};
  Rendered r[3];
  for (int s = 0; s < 3; ++s) r[s] = render_scene(room_scene(names[s], 256, 11 + s));
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      for (int by = 0; by < 24; by += 4)
        for (int bx = 0; bx < 24; bx += 4)
          for (int c = 0; c < 3; ++c) {
            double ma = 0, mb = 0, va = 0, vb = 0;
            for (int y = by; y < by + 4; ++y)
              for (int x = bx; x < bx + 4; ++x) {
                ma += r[a].mean.at(x, y)[c], va += r[a].variance.at(x, y)[c];
                mb += r[b].mean.at(x, y)[c], vb += r[b].variance.at(x, y)[c];
              }
            EXPECT_LE(std::fabs(ma - mb), 4.5 * std::sqrt(va + vb) + 1e-6)
                << names[a] << " vs " << names[b] << " block " << bx << "," << by << " channel "
                << c << ": " << ma / 16 << " vs " << mb / 16;
          }
}

/// Veach's multiple importance sampling scene, as our own: four rough metal plates of falling
/// roughness below four spherical lights of falling size and equal power, seen so that each plate
/// reflects every light.
std::string veach_scene(const std::string& strategy) {
  std::string shapes;
  const float roughness[4] = {0.55f, 0.35f, 0.2f, 0.1f};
  for (int i = 0; i < 4; ++i) {
    const float z = -1.2f + 0.8f * float(i), tilt = 0.35f - 0.12f * float(i);
    shapes += fmt::format(R"({{"type": "quad", "origin": [-2, {}, {}], "edge1": [4, 0, 0],
        "edge2": [0, {}, 0.7], "material": "plate{}"}},)",
                          -tilt * 0.5f, z, tilt, i);
  }
  const float radius[4] = {0.5f, 0.15f, 0.05f, 0.015f};
  for (int i = 0; i < 4; ++i) {
    const float l = 0.8f * 0.25f / (radius[i] * radius[i]);  // equal power: L r^2 fixed
    shapes += fmt::format(R"({{"type": "sphere", "center": [{}, 2.2, 2.2], "radius": {},
        "material": "black", "emission": [{}, {}, {}]}}{})",
                          -1.5f + 1.0f * float(i), radius[i], l, l, l, i < 3 ? "," : "");
  }
  std::string materials = R"("black": {"type": "diffuse", "albedo": [0, 0, 0]})";
  for (int i = 0; i < 4; ++i)
    materials += fmt::format(R"(, "plate{}": {{"type": "conductor", "reflectance": [0.8, 0.8, 0.8],
        "roughness": {}}})",
                             i, roughness[i]);
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 1.6, -4.5], "look_at": [0, 0, 0], "vfov": 38}},
    "render": {{"resolution": [48, 32], "spp": 64, "seed": 2, "integrator": "path:strategy={},max_depth=1"}},
    "materials": {{{}}},
    "shapes": [{}]
  }})",
                     strategy, materials, shapes);
}

// On Veach's scene light sampling wins on the rough plates and the large lights, BSDF sampling on
// the smooth plates and the small lights; MIS is close to the better of the two everywhere, so
// its total variance is below both.
TEST(PathStrategies, MisHasTheLowestVarianceOnVeachsScene) {
  double total[3] = {0, 0, 0};
  const char* names[3] = {"mis", "nee", "bsdf"};
  for (int s = 0; s < 3; ++s) {
    const Rendered r = render_scene(veach_scene(names[s]));
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 48; ++x) total[s] += r.variance.at(x, y).g;
  }
  EXPECT_LT(total[0], 0.8 * total[1]) << "mis " << total[0] << " nee " << total[1];
  EXPECT_LT(total[0], 0.8 * total[2]) << "mis " << total[0] << " bsdf " << total[2];
}

// Convergence on the Cornell box: the RMSE against a long render falls as spp^(-1/2). The
// reference's own variance (estimated from its samples) is taken out of each MSE before the fit.
TEST(PathConvergence, CornellBoxRmseFallsAsInverseSquareRootOfSpp) {
  SceneDesc desc = test::bundled_scene("cornell-box.json");
  desc.render.width = desc.render.height = 32;
  desc.render.integrator = "path";
  desc.render.sampler = "independent";
  desc.render.spp = 2048;
  desc.render.seed = 1000;
  RenderJob ref_job(desc);
  ref_job.run();
  const RgbImage ref = ref_job.film->resolve(), ref_var = ref_job.film->variance();
  double ref_mse = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) ref_mse += ref_var.at(x, y).g;
  ref_mse /= 1024.0;

  std::vector<double> xs, ys;
  for (int spp = 4; spp <= 256; spp *= 2) {
    desc.render.spp = spp;
    desc.render.seed = uint64_t(spp);
    RenderJob job(desc);
    job.run();
    const RgbImage img = job.film->resolve();
    double mse = 0;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const double d = double(img.at(x, y).g) - double(ref.at(x, y).g);
        mse += d * d;
      }
    mse = mse / 1024.0 - ref_mse;
    ASSERT_GT(mse, 0.0);
    xs.push_back(std::log(double(spp)));
    ys.push_back(0.5 * std::log(mse));  // log RMSE
  }
  double mx = 0, my = 0;
  for (size_t i = 0; i < xs.size(); ++i) mx += xs[i], my += ys[i];
  mx /= double(xs.size()), my /= double(xs.size());
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    sxy += (xs[i] - mx) * (ys[i] - my);
    sxx += (xs[i] - mx) * (xs[i] - mx);
  }
  const double slope = sxy / sxx;
  EXPECT_GE(slope, -0.55);
  EXPECT_LE(slope, -0.45);
}

}  // namespace
}  // namespace penumbra
