// Every registered acceleration structure renders the same image.
#include <gtest/gtest.h>

#include <filesystem>

#include "penumbra/accel/registry.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

// The Cornell box with each structure gives an image bit-identical to brute force's: the
// structures must find the same closest hit for every camera, shadow and secondary ray.
TEST(EveryStructure, CornellBoxImagesAreBitIdentical) {
  auto desc = test::bundled_scene("cornell-box.json");
  desc.render.width = 96;
  desc.render.height = 96;
  desc.render.spp = 2;
  desc.render.accel = "brute";
  const RgbImage reference = test::render_desc(desc);
  for (const AccelInfo& info : accelerator_list()) {
    desc.render.accel = info.name;
    const RgbImage image = test::render_desc(desc);
    EXPECT_TRUE(image == reference) << info.name;
  }
}

// The same for spheres and parallelograms with a mirror and glass (whitted.json), and for a
// scanned mesh (mesh-bunny.json).
TEST(EveryStructure, WhittedShowcaseImagesAreBitIdentical) {
  auto desc = test::bundled_scene("whitted.json");
  desc.render.width = 80;
  desc.render.height = 60;
  desc.render.spp = 1;
  desc.render.accel = "brute";
  const RgbImage reference = test::render_desc(desc);
  for (const AccelInfo& info : accelerator_list()) {
    desc.render.accel = info.name;
    EXPECT_TRUE(test::render_desc(desc) == reference) << info.name;
  }
}

TEST(EveryStructure, BunnyImagesAreBitIdentical) {
  auto desc = test::bundled_scene("mesh-bunny.json");
  desc.render.width = 80;
  desc.render.height = 60;
  desc.render.spp = 1;
  desc.render.accel = "brute";
  const RgbImage reference = test::render_desc(desc);
  for (const AccelInfo& info : accelerator_list()) {
    desc.render.accel = info.name;
    EXPECT_TRUE(test::render_desc(desc) == reference) << info.name;
  }
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

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

}  // namespace
}  // namespace penumbra
