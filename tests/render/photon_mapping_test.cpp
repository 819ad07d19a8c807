// The photon-mapping integrators against exact answers and against the path tracer: a closed
// emissive enclosure, the Cornell box region by region, a caustic, determinism at any thread
// count, and SPPM's render loop (time limit, cancellation, checkpoints).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/render/integrator/photon_integrator.h"
#include "penumbra/render/render_job.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// Inside a sphere of radius 2 with two-sided emission E = 0.5 and albedo 0.6, every point sees
/// L = E / (1 - rho) = 1.25 from every direction.
std::string enclosure(const std::string& integrator, int spp, int seed) {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0.1, 0.2, -0.3], "look_at": [0.5, 0, 1],
                "vfov": 90}},
    "render": {{"resolution": [8, 8], "spp": {}, "seed": {}, "integrator": "{}"}},
    "materials": {{"m": {{"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}}}},
    "shapes": [{{"type": "sphere", "center": [0, 0, 0], "radius": 2, "material": "m",
                 "emission": [0.5, 0.5, 0.5], "two_sided": true}}]
  }})",
                     spp, seed, integrator);
}

/// Mean over the image of the green channel.
double image_mean(const RgbImage& img) {
  double s = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) s += img.at(x, y).g;
  return s / double(img.width() * img.height());
}

/// Renders `make(seed)` for `seeds` seeds and expects the mean of their image means within 4
/// standard errors (from the spread across seeds) of `expected`.
template <class Make>
void expect_mean_across_seeds(Make make, int seeds, double expected) {
  std::vector<double> means;
  for (int s = 0; s < seeds; ++s)
    means.push_back(image_mean(test::render_desc(test::scene_from_text(make(s)))));
  double m = 0, v = 0;
  for (double x : means) m += x;
  m /= seeds;
  for (double x : means) v += (x - m) * (x - m);
  const double se = std::sqrt(v / (seeds - 1) / seeds);
  EXPECT_GT(se, 0.0);  // the estimates are noisy: the bound means something
  EXPECT_LE(std::fabs(m - expected), 4.0 * se) << "mean " << m << " standard error " << se;
}

// In the uniform enclosure the photon density is uniform, where both density estimates are
// unbiased: SPPM's disc around a visible point (on a sphere the cap within distance r has area
// pi r^2 exactly, Archimedes) and the k-nearest estimate with the Epanechnikov kernel (the k-1
// photons inside the k-th neighbour's disc have mean weight 1/2 and E[1 / (pi r_k^2)] =
// density / (k - 1)). So both must reach 1.25 within their statistical error.
TEST(SppmEnclosure, ClosedEmissiveSphereReachesEOverOneMinusRho) {
  expect_mean_across_seeds(
      [](int s) { return enclosure("sppm:photons=4000,radius=0.15", 24, 10 + s); }, 8, 1.25);
}
TEST(PhotonEnclosure, ClosedEmissiveSphereReachesEOverOneMinusRho) {
  for (const char* irradiance : {"true", "false"}) {
    SCOPED_TRACE(irradiance);
    expect_mean_across_seeds(
        [&](int s) {
          return enclosure(
              fmt::format("photon:photons=20000,k=50,gather=4,irradiance={}", irradiance), 8,
              20 + s);
        },
        8, 1.25);
  }
}

/// Expects every region mean of `got` within `tolerance` (relative, per channel above 0.02) of
/// the reference's.
void expect_regions_agree(const RgbImage& got, const RgbImage& ref, double tolerance) {
  for (const test::ImageRegion& r : test::kCornellRegions64) {
    const Rgb a = test::region_mean(got, r.x0, r.y0, r.x1, r.y1);
    const Rgb b = test::region_mean(ref, r.x0, r.y0, r.x1, r.y1);
    for (int c = 0; c < 3; ++c) {
      if (b[c] < 0.02f) continue;
      EXPECT_LE(std::fabs(a[c] / b[c] - 1.0f), tolerance)
          << r.name << " channel " << c << ": " << a[c] << " vs path " << b[c];
    }
  }
}

// The issue's agreement targets: sppm after many passes within 2% of path on every region,
// photon with its default parameters within 5%. path's own error at 1024 spp on these regions
// (>= 60 pixels each) is below 0.3%.
TEST(PhotonMappingCornellBox, SppmAndPhotonAgreeWithPathOnEveryRegion) {
  const RgbImage path = test::cornell_box("path", 64, 1024);
  expect_regions_agree(test::cornell_box("sppm:photons=40000", 64, 256), path, 0.02);
  expect_regions_agree(test::cornell_box("photon", 64, 64), path, 0.05);
}

// Photons traced and gathered in fixed chunks, visible points per pixel: the same bits on one
// thread as on all.
TEST(PhotonMappingDeterminism, SameBitsAtAnyThreadCount) {
  for (const char* integrator : {"sppm:photons=5000", "photon:photons=5000,caustic_photons=2000"}) {
    SCOPED_TRACE(integrator);
    EXPECT_TRUE(test::cornell_box(integrator, 24, 4, 1) == test::cornell_box(integrator, 24, 4, 2));
  }
}

// An open scene with a thin lens (scenes/depth-of-field.json: spheres on a 40 x 40 floor): each
// pixel's initial radius follows its own footprint, so the blur is a couple of pixels everywhere
// and every 8 x 8 block of sppm matches path within 6% (with one radius from the scene's size,
// 1.8 units against spheres of radius 0.5, the spheres' blocks read 25-28% dark).
TEST(SppmCameraEffects, OpenSceneWithThinLensMatchesPathBlockByBlock) {
  auto desc = test::bundled_scene("depth-of-field.json");
  desc.render.width = 64;
  desc.render.height = 48;
  desc.render.max_depth.reset();
  desc.render.spp = 1024;
  desc.render.integrator = "path";
  const RgbImage path = test::render_desc(desc);
  desc.render.spp = 256;
  desc.render.integrator = "sppm:photons=50000";
  const RgbImage sppm = test::render_desc(desc);
  int blocks = 0;
  for (int by = 0; by < 48; by += 8)
    for (int bx = 0; bx < 64; bx += 8) {
      const float a = test::region_mean(sppm, bx, by, bx + 8, by + 8).g;
      const float b = test::region_mean(path, bx, by, bx + 8, by + 8).g;
      if (b < 0.01f) continue;
      ++blocks;
      EXPECT_LE(std::fabs(a / b - 1.0f), 0.06f)
          << "block " << bx << "," << by << ": " << a << " vs path " << b;
    }
  EXPECT_GE(blocks, 24);
}

/// The bundled caustic scene at 64 x 48.
RgbImage caustic_scene(const std::string& integrator, int spp) {
  auto desc = test::bundled_scene("caustic.json");
  desc.render.width = 64;
  desc.render.height = 48;
  desc.render.spp = spp;
  desc.render.integrator = integrator;
  return test::render_desc(desc);
}

// The glass sphere's caustic lies where path puts it: on the pixels where a long path render is
// brightest on the floor, sppm and photon's caustic map are bright too, and photon's caustic map
// is dark on the floor far from the sphere.
TEST(PhotonMappingCaustic, CausticAppearsWherePathPutsIt) {
  const RgbImage path = caustic_scene("path", 2048);
  const RgbImage sppm = caustic_scene("sppm:photons=40000", 128);
  const RgbImage shown = caustic_scene("photon:show=caustic,caustic_photons=400000", 1);
  // The caustic: floor pixels below the sphere whose path radiance is at least twice the lit
  // floor's level at the image's bottom edge.
  const double floor_level = test::region_mean(path, 0, 44, 64, 48).g;
  ASSERT_GT(floor_level, 0.0);
  double path_sum = 0, sppm_sum = 0, shown_sum = 0;
  int n = 0;
  for (int y = 24; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      if (path.at(x, y).g > 2.0 * floor_level) {
        path_sum += path.at(x, y).g, sppm_sum += sppm.at(x, y).g, shown_sum += shown.at(x, y).g;
        ++n;
      }
  ASSERT_GE(n, 4) << "no caustic in the path render";
  EXPECT_LE(std::fabs(sppm_sum / path_sum - 1.0), 0.15)
      << "sppm " << sppm_sum / n << " path " << path_sum / n;
  EXPECT_GT(shown_sum / n, floor_level) << "the caustic map is not bright on the caustic";
  EXPECT_LT(test::region_mean(shown, 0, 44, 16, 48).g, 0.05 * floor_level)
      << "the caustic map holds light far from the sphere";
}

// photon's preprocessing fills both maps where they should be filled: the Cornell box has no
// specular surface, so no caustic photon; the caustic scene has both.
TEST(PhotonMaps, CausticMapHoldsOnlyLightThroughSpecularSurfaces) {
  for (const char* scene : {"cornell-box.json", "caustic.json"}) {
    SCOPED_TRACE(scene);
    auto desc = test::bundled_scene(scene);
    desc.render.width = desc.render.height = 8;
    desc.render.spp = 1;
    desc.render.integrator = "photon:photons=20000,caustic_photons=20000";
    RenderJob job(desc);
    job.run();
    const auto& pi = dynamic_cast<const PhotonIntegrator&>(*job.integrator);
    EXPECT_GT(pi.global_map().size(), 20000u);  // more than one hit per photon on average
    if (std::string(scene) == "cornell-box.json") {
      EXPECT_EQ(pi.caustic_map().size(), 0u);
    } else {
      EXPECT_GT(pi.caustic_map().size(), 100u);
      EXPECT_LT(pi.caustic_map().size(), 20000u);
    }
    EXPECT_GT(pi.irradiance_points(), pi.global_map().size() / 5);
  }
}

// SPPM runs its own loop: passes stop at a time limit between passes, cancellation keeps the
// finished passes' estimate, checkpoints come between passes, and a target error is refused
// (SPPM estimates no per-pixel variance).
TEST(SppmLoop, TimeLimitCancellationCheckpointsAndTargetError) {
  auto desc = test::bundled_scene("cornell-box.json");
  desc.render.width = desc.render.height = 32;
  desc.render.spp = 1 << 20;
  desc.render.integrator = "sppm:photons=2000";
  {
    RenderJob job(desc);
    job.options.time_limit_s = 0.5;
    int checkpoints = 0;
    job.options.checkpoint_s = 1e-9;
    job.options.on_checkpoint = [&](const Film&, int) { ++checkpoints; };
    const RenderStats s = job.run();
    EXPECT_EQ(s.stop, StopReason::kTimeLimit);
    EXPECT_GT(s.spp_done, 1);
    EXPECT_LT(s.seconds, 2.0);
    EXPECT_EQ(checkpoints, s.spp_done)
        << "a checkpoint after every pass (the target is never reached)";
    EXPECT_EQ(job.film->samples(5, 5), uint32_t(s.spp_done));
  }
  {
    RenderJob job(desc);
    std::atomic<bool> cancel{false};
    job.options.cancel = &cancel;
    int passes = 0;
    job.options.on_progress = [&](const RenderProgress& p) {
      passes = p.spp_done;
      if (p.spp_done >= 3) cancel = true;
    };
    const RenderStats s = job.run();
    EXPECT_EQ(s.stop, StopReason::kCancelled);
    EXPECT_GE(s.spp_done, 3);
    EXPECT_GT(job.film->resolve().at(16, 16).max_channel(), 0.0f);
  }
  {
    RenderJob job(desc);
    job.options.target_error = 0.01;
    EXPECT_THROW(job.run(), Error);
  }
}

}  // namespace
}  // namespace penumbra
