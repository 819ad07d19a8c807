// The progressive render loop: pass schedules, thread counts, stopping rules, the integrator's
// hooks and the per-pixel variance estimate.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "penumbra/core/parallel.h"
#include "penumbra/render/render_job.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// A small lit scene: a diffuse floor and sphere under a quad light and a dim sky.
std::string scene_json(const std::string& sampler, int spp,
                       const std::string& integrator = "path") {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 1, -3], "look_at": [0, 0.3, 0], "vfov": 50}},
    "render": {{"resolution": [20, 14], "spp": {}, "seed": 4, "sampler": "{}",
                "integrator": "{}", "background": [0.1, 0.15, 0.2]}},
    "materials": {{"white": {{"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
                  "metal": {{"type": "conductor", "reflectance": [0.9, 0.6, 0.3], "roughness": 0.3}}}},
    "shapes": [
      {{"type": "quad", "origin": [-2, 0, -2], "edge1": [0, 0, 4], "edge2": [4, 0, 0], "material": "white"}},
      {{"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "metal"}},
      {{"type": "quad", "origin": [-0.5, 2, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1],
        "material": "white", "emission": [5, 5, 5]}}
    ]
  }})",
                     spp, sampler, integrator);
}

/// Renders with a fixed pass size (0: the adaptive schedule) on `threads` workers.
RgbImage render_with(const std::string& json, int pass_spp, int threads) {
  const ThreadLimit limit(threads);
  RenderJob job(test::scene_from_text(json));
  job.options.pass_spp = pass_spp;
  job.options.tile_size = 7;  // tiles that do not divide the image
  const RenderStats stats = job.run();
  EXPECT_TRUE(stats.complete());
  EXPECT_EQ(stats.spp_done, job.sampler->samples_per_pixel());
  return job.film->resolve();
}

// A sample's numbers depend only on (pixel, index, seed) and each pixel sums its samples in index
// order: any pass schedule and any thread count give the same bits, for every sampler.
TEST(RenderLoop, AnyPassScheduleAndThreadCountGiveTheSameBits) {
  for (const char* sampler : {"independent", "jittered", "sobol"}) {
    SCOPED_TRACE(sampler);
    const std::string json = scene_json(sampler, 12);
    const RgbImage reference = render_with(json, 12, 1);
    EXPECT_TRUE(render_with(json, 1, 2) == reference);
    EXPECT_TRUE(render_with(json, 5, 2) == reference);  // passes of 5, 5 and 2
    EXPECT_TRUE(render_with(json, 0, 2) == reference);  // the adaptive schedule
    EXPECT_FALSE(render_with(scene_json(sampler, 11), 0, 2) == reference);
  }
}

/// Counts the integrator's lifecycle calls around the path tracer.
class CountingIntegrator final : public SamplingIntegrator {
 public:
  explicit CountingIntegrator(std::unique_ptr<Integrator> inner)
      : inner_(dynamic_cast<SamplingIntegrator*>(inner.release())) {}
  std::string name() const override { return "counting"; }
  void preprocess(RenderJob&) override { ++preprocessed; }
  void end_pass(RenderJob&, int spp_done) override { pass_ends.push_back(spp_done); }
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override {
    EXPECT_EQ(preprocessed, 1);  // preprocessing is over before the first sample
    return inner_->li(ray, sampler, counter);
  }
  int preprocessed = 0;
  std::vector<int> pass_ends;

 private:
  std::unique_ptr<SamplingIntegrator> inner_;
};

TEST(RenderLoop, PreprocessRunsOnceBeforeTheFirstPassAndEndPassAfterEach) {
  RenderJob job(test::scene_from_text(scene_json("independent", 10)));
  auto counting = std::make_unique<CountingIntegrator>(std::move(job.integrator));
  CountingIntegrator& c = *counting;
  job.integrator = std::move(counting);
  job.options.pass_spp = 4;
  const RenderStats stats = job.run();
  EXPECT_EQ(c.preprocessed, 1);
  EXPECT_EQ(c.pass_ends, (std::vector<int>{4, 8, 10}));
  EXPECT_EQ(stats.passes, 3);
}

// Cancelling in the middle of the third pass keeps the two finished passes everywhere and the
// finished tiles of the third: every pixel has samples, none is black.
TEST(RenderLoop, CancelledRenderKeepsEveryFinishedSample) {
  RenderJob job(test::scene_from_text(scene_json("independent", 64)));
  std::atomic<bool> cancel{false};
  std::atomic<int> tiles{0};
  job.options.cancel = &cancel;
  job.options.pass_spp = 2;
  job.options.tile_size = 4;  // 5 x 4 = 20 tiles a pass
  job.options.on_progress = [&](const RenderProgress&) {
    if (++tiles == 45) cancel = true;
  };
  const ThreadLimit one(1);
  const RenderStats stats = job.run();
  EXPECT_EQ(stats.stop, StopReason::kCancelled);
  EXPECT_FALSE(stats.complete());
  EXPECT_EQ(stats.spp_done, 4);
  EXPECT_EQ(stats.tiles_done, 5u);
  for (int y = 0; y < 14; ++y)
    for (int x = 0; x < 20; ++x) {
      const uint32_t n = job.film->samples(x, y);
      EXPECT_TRUE(n == 4 || n == 6) << x << "," << y << ": " << n;
    }
  const RgbImage img = job.film->resolve();
  for (int y = 0; y < 14; ++y)
    for (int x = 0; x < 20; ++x) EXPECT_GT(img.at(x, y).max_channel(), 0.0f);
}

// A time limit ends the render between passes with the same number of samples in every pixel.
TEST(RenderLoop, TimeLimitStopsBetweenPasses) {
  RenderJob job(test::scene_from_text(scene_json("independent", 1 << 20)));
  job.options.time_limit_s = 0.3;
  const RenderStats stats = job.run();
  EXPECT_EQ(stats.stop, StopReason::kTimeLimit);
  EXPECT_TRUE(stats.complete());
  EXPECT_GT(stats.spp_done, 0);
  EXPECT_LT(stats.spp_done, 1 << 20);
  // Passes are sized by the pace so far; a loaded machine may slow the last one down.
  EXPECT_LT(stats.seconds, 0.3 * 2.0 + 0.5);
  for (int y = 0; y < 14; ++y)
    for (int x = 0; x < 20; ++x) EXPECT_EQ(job.film->samples(x, y), uint32_t(stats.spp_done));
}

// An error target ends the render once the mean relative standard error is below it; a tighter
// target takes more samples.
TEST(RenderLoop, TargetErrorStopsWhenTheImageIsPreciseEnough) {
  int spp[2];
  const double targets[2] = {0.08, 0.04};
  for (int i = 0; i < 2; ++i) {
    RenderJob job(test::scene_from_text(scene_json("independent", 1 << 16)));
    job.options.target_error = targets[i];
    const RenderStats stats = job.run();
    EXPECT_EQ(stats.stop, StopReason::kTargetError);
    EXPECT_LE(stats.mean_rel_error, targets[i]);
    EXPECT_NEAR(job.film->mean_relative_error(), stats.mean_rel_error, 1e-12);
    spp[i] = stats.spp_done;
  }
  // The error falls as spp^-1/2: halving it takes about four times the samples.
  EXPECT_GT(spp[1], 2 * spp[0]);
}

// Checkpoints come between passes with a growing number of samples.
TEST(RenderLoop, CheckpointsComeBetweenPasses) {
  RenderJob job(test::scene_from_text(scene_json("independent", 40)));
  job.options.pass_spp = 8;
  job.options.checkpoint_s = 1e-9;  // after every pass but the last
  std::vector<int> seen;
  job.options.on_checkpoint = [&](const Film& film, int spp) {
    EXPECT_EQ(film.samples(0, 0), uint32_t(spp));
    seen.push_back(spp);
  };
  job.run();
  EXPECT_EQ(seen, (std::vector<int>{8, 16, 24, 32}));
}

// The per-pixel variance estimate agrees with the spread of independent renders: over many
// pixels, the mean estimated variance of a pixel's mean and the mean empirical variance of the
// pixel across 24 seeds agree within 15% (the empirical variance has 23 degrees of freedom per
// pixel, over 280 pixels: relative error about 2%).
TEST(RenderLoop, VarianceEstimateMatchesTheSpreadAcrossSeeds) {
  constexpr int kRuns = 24;
  std::vector<RgbImage> means;
  double estimated = 0;
  for (int run = 0; run < kRuns; ++run) {
    SceneDesc desc = test::scene_from_text(scene_json("independent", 16));
    desc.render.seed = uint64_t(100 + run);
    RenderJob job(desc);
    job.run();
    means.push_back(job.film->resolve());
    const RgbImage v = job.film->variance();
    for (int y = 0; y < 14; ++y)
      for (int x = 0; x < 20; ++x) estimated += v.at(x, y).g;
  }
  estimated /= kRuns;
  double empirical = 0;
  for (int y = 0; y < 14; ++y)
    for (int x = 0; x < 20; ++x) {
      double m = 0, m2 = 0;
      for (const RgbImage& img : means)
        m += img.at(x, y).g, m2 += double(img.at(x, y).g) * img.at(x, y).g;
      m /= kRuns;
      empirical += (m2 - kRuns * m * m) / (kRuns - 1);
    }
  EXPECT_GT(estimated, 0.0);
  EXPECT_NEAR(estimated / empirical, 1.0, 0.15) << estimated << " vs " << empirical;
}

}  // namespace
}  // namespace penumbra
