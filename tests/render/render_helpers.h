#pragma once
// Shared helpers of the render tests: scenes from JSON text, and rendering them in memory.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>

#include "penumbra/core/parallel.h"
#include "penumbra/render/camera/camera_registry.h"
#include "penumbra/render/film.h"
#include "penumbra/render/filter/filter.h"
#include "penumbra/render/integrator/integrator_registry.h"
#include "penumbra/render/render_job.h"
#include "penumbra/render/renderer.h"
#include "penumbra/render/sampler/sampler_registry.h"
#include "penumbra/render/world.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::test {

/// Renders `desc` with its own settings on `threads` workers (0 = all).
inline RgbImage render_desc(const SceneDesc& desc, int threads = 0) {
  const ThreadLimit limit(threads);
  RenderJob job(desc);
  job.run();
  return job.film->resolve();
}

/// The number of channel values in which two images differ (a size mismatch is a failure and
/// counts every value of the larger image).
inline size_t differing_values(const RgbImage& a, const RgbImage& b) {
  EXPECT_EQ(a.width(), b.width());
  EXPECT_EQ(a.height(), b.height());
  if (a.width() != b.width() || a.height() != b.height()) return 3 * std::max(a.size(), b.size());
  size_t n = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < 3; ++c) n += a.at(x, y)[c] != b.at(x, y)[c];
  return n;
}

/// Parses scene JSON text (meshes relative to the repository root).
inline SceneDesc scene_from_text(const std::string& json) {
  return parse_scene(json, "test.json", PENUMBRA_SOURCE_DIR);
}

/// Loads a bundled scene from scenes/.
inline SceneDesc bundled_scene(const std::string& name) {
  return load_scene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name);
}

/// The bundled Cornell box at w x w with `integrator` and `spp`, on `threads` workers (0 = all).
inline RgbImage cornell_box(const std::string& integrator, int w, int spp, int threads = 0) {
  auto desc = bundled_scene("cornell-box.json");
  desc.render.width = desc.render.height = w;
  desc.render.spp = spp;
  desc.render.integrator = integrator;
  return render_desc(desc, threads);
}

/// Mean of each channel over the pixel rectangle [x0, x1) x [y0, y1).
inline Rgb region_mean(const RgbImage& img, int x0, int y0, int x1, int y1) {
  double s[3] = {0, 0, 0};
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int c = 0; c < 3; ++c) s[c] += img.at(x, y)[c];
  const double n = double((x1 - x0) * (y1 - y0));
  return {float(s[0] / n), float(s[1] / n), float(s[2] / n)};
}

/// A named pixel rectangle of an image.
struct ImageRegion {
  const char* name;
  int x0, y0, x1, y1;
};
/// Regions of the 64 x 64 Cornell box: left (red) and right (green) walls, back wall, floor and
/// ceiling, away from edges and blocks.
inline constexpr ImageRegion kCornellRegions64[] = {{"red wall", 3, 20, 9, 44},
                                                    {"green wall", 55, 20, 61, 44},
                                                    {"back wall", 24, 12, 40, 22},
                                                    {"floor", 14, 57, 50, 62},
                                                    {"ceiling", 14, 2, 24, 6}};

}  // namespace penumbra::test
