// Every registered acceleration structure renders the same image.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "penumbra/accel/registry.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// Renders bundled scene `name` at w x h with `spp` samples with every registered structure and
/// expects images bit-identical to brute force's: every structure must find the same closest hit
/// for every camera, shadow and secondary ray.
void expect_identical_images(const std::string& name, int w, int h, int spp) {
  auto desc = test::bundled_scene(name);
  desc.render.width = w;
  desc.render.height = h;
  desc.render.spp = spp;
  desc.render.accel = "brute";
  const RgbImage reference = test::render_desc(desc);
  for (const AccelInfo& info : accelerator_list()) {
    desc.render.accel = info.name;
    EXPECT_TRUE(test::render_desc(desc) == reference) << name << " with " << info.name;
  }
}

// Triangles in the Cornell box; spheres and parallelograms with a mirror and glass
// (whitted.json); a scanned mesh (mesh-bunny.json).
TEST(EveryStructure, CornellBoxImagesAreBitIdentical) {
  expect_identical_images("cornell-box.json", 96, 96, 2);
}
TEST(EveryStructure, WhittedShowcaseImagesAreBitIdentical) {
  expect_identical_images("whitted.json", 80, 60, 1);
}
TEST(EveryStructure, BunnyImagesAreBitIdentical) {
  expect_identical_images("mesh-bunny.json", 80, 60, 1);
}


// Every bundled scene loads and renders (tiny, one sample) with its own settings, and some pixel
// receives light.
TEST(BundledScenes, EveryBundledSceneRendersLight) {
  int scenes = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(PENUMBRA_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    ++scenes;
    auto desc = load_scene(entry.path().string());
    desc.render.width = 24;
    desc.render.height = 16;
    desc.render.spp = 1;
    const RgbImage img = test::render_desc(desc);
    float max = 0;
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x) max = std::max(max, img.at(x, y).max_channel());
    EXPECT_GT(max, 0.0f) << entry.path();
  }
  EXPECT_GE(scenes, 5);
}

// `path` renders every bundled scene, whatever its materials, lights, textures, camera (the thin
// lens of depth-of-field.json) and motion (motion-blur.json): finite pixels, some light, and the
// same bits on one and two threads.
TEST(BundledScenes, PathTracesEveryBundledScene) {
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(PENUMBRA_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    auto desc = load_scene(entry.path().string());
    desc.render.width = 24;
    desc.render.height = 16;
    desc.render.spp = 4;
    desc.render.integrator = "path";
    const RgbImage img = test::render_desc(desc, 2);
    float max = 0;
    bool finite = true;
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x) {
        const Rgb c = img.at(x, y);
        // (Negative values are legitimate: Mitchell's filter has negative lobes.)
        finite = finite && std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
        max = std::max(max, c.max_channel());
      }
    EXPECT_TRUE(finite) << entry.path();
    // Some light, unless the scene has none (zone-plate.json is a texture seen in albedo mode).
    if (!World(desc, "bvh").lights().empty()) {
      EXPECT_GT(max, 0.0f) << entry.path();
    }
    EXPECT_TRUE(test::render_desc(desc, 1) == img) << entry.path();
  }
}

}  // namespace
}  // namespace penumbra
