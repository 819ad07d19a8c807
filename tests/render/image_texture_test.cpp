/// Image textures: the documented pixel layout (t = 1 at the top row), bilinear lookup, wrap
/// modes, uv scale and offset, the JSON syntax with its errors, and pbrt-v4's imagemap.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "../image/temp_dir.h"
#include "penumbra/core/error.h"
#include "penumbra/image/pfm.h"
#include "penumbra/image/png.h"
#include "penumbra/render/material/material_registry.h"
#include "penumbra/render/texture/texture.h"
#include "penumbra/scene/scene_loader.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

// A 4 x 2 image of distinct colours: pixel (x, y) = (x / 4, y / 2, 0.25 + 0.1 x y).
std::shared_ptr<const RgbImage> grid_image() {
  auto image = std::make_shared<RgbImage>(4, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) image->at(x, y) = Rgb(x / 4.0f, y / 2.0f, 0.25f + 0.1f * x * y);
  return image;
}

Rgb at(const Texture& t, float u, float v) {
  return t.eval(TextureQuery{{}, {u, v}});
}

void expect_near(Rgb a, Rgb b, float tol = 1e-6f) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << "channel " << c;
}

TEST(ImageTexture, PixelCentresShowTheirPixelsWithTheTopRowAtVOne) {
  const auto image = grid_image();
  const Texture t = Texture::image(image, {1, 1}, {0, 0}, Texture::Wrap::kClamp);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x)
      expect_near(at(t, (x + 0.5f) / 4, 1 - (y + 0.5f) / 2), image->at(x, y));
  // Half-way between two centres: the mean (bilinear).
  expect_near(at(t, 0.25f, 0.75f), (image->at(0, 0) + image->at(1, 0)) * 0.5f);
  expect_near(at(t, 0.125f, 0.5f), (image->at(0, 0) + image->at(0, 1)) * 0.5f);
}

TEST(ImageTexture, WrapModesScaleAndOffset) {
  const auto image = grid_image();
  const Texture repeat = Texture::image(image, {1, 1}, {0, 0}, Texture::Wrap::kRepeat);
  const Texture clamp = Texture::image(image, {1, 1}, {0, 0}, Texture::Wrap::kClamp);
  const Texture black = Texture::image(image, {1, 1}, {0, 0}, Texture::Wrap::kBlack);
  for (float u : {0.1f, 0.37f, 0.8f})
    for (float v : {0.2f, 0.6f}) {
      expect_near(at(repeat, u + 3, v - 2), at(repeat, u, v), 1e-5f);
      expect_near(at(repeat, u - 1000, v + 500), at(repeat, u, v), 1e-3f);
    }
  // Across the left edge: repeat blends with the right column, clamp keeps the left one.
  expect_near(at(repeat, 0.0f, 0.75f), (image->at(0, 0) + image->at(3, 0)) * 0.5f);
  expect_near(at(clamp, -0.3f, 0.75f), image->at(0, 0));
  expect_near(at(black, -0.3f, 0.75f), Rgb(0.0f));
  expect_near(at(black, 0.0f, 0.75f), image->at(0, 0) * 0.5f);
  // (s, t) = (u su + du, v sv + dv).
  const Texture scaled = Texture::image(image, {2, 4}, {0.1f, -0.2f}, Texture::Wrap::kClamp);
  expect_near(at(scaled, 0.2f, 0.2f), at(clamp, 0.5f, 0.6f), 1e-6f);
  // Non-finite or enormous uv never reads outside the image.
  EXPECT_TRUE(std::isfinite(at(repeat, 1e30f, -1e30f).r));
  EXPECT_TRUE(std::isfinite(at(repeat, std::nanf(""), 0.5f).r));
}

// The JSON syntax: "file" relative to the scene file, read once for every material that names
// it; pixels outside the parameter's range and bad keys are errors at their JSON path.
TEST(ImageTexture, SceneFilesNameImagesRelativeToThemselves) {
  const test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "tex");
  write_pfm(*grid_image(), dir.file("tex/grid.pfm"));
  RgbImage bright(2, 2, Rgb(0.5f));
  bright.at(1, 0) = Rgb(0.5f, 2.0f, 0.5f);
  write_pfm(bright, dir.file("tex/bright.pfm"));
  test::write_bytes(dir.file("scene.json"), R"({
    "camera": {"type": "pinhole"},
    "materials": {
      "a": {"type": "diffuse", "albedo": {"type": "image", "file": "tex/grid.pfm", "wrap": "clamp"}},
      "b": {"type": "diffuse", "albedo": {"type": "image", "file": "tex/bright.pfm"}},
      "c": {"type": "diffuse", "albedo": {"type": "image", "file": "tex/grid.pfm", "wrap": "spiral"}},
      "d": {"type": "diffuse", "albedo": {"type": "image", "file": "tex/none.pfm"}}},
    "shapes": []})");
  const SceneDesc desc = load_scene(dir.file("scene.json"));
  ASSERT_EQ(desc.materials.size(), 4u);
  const auto material = make_material(desc.materials[0].params);
  SurfaceInteraction si;
  MaterialScratch scratch;
  si.uv = {0.375f, 0.25f};  // the centre of pixel (1, 1)
  expect_near(material->at(si, scratch).albedo(), grid_image()->at(1, 1));
  const auto error_of = [&](size_t i) -> std::string {
    try {
      make_material(desc.materials[i].params);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(error_of(1).find("/materials/b/albedo/file: "), std::string::npos) << error_of(1);
  EXPECT_NE(error_of(1).find("pixel (1, 0) is 2"), std::string::npos) << error_of(1);
  EXPECT_NE(error_of(2).find("/materials/c/albedo/wrap: unknown wrap"), std::string::npos)
      << error_of(2);
  EXPECT_NE(error_of(3).find("/materials/d/albedo/file: image not found"), std::string::npos)
      << error_of(3);
}

// pbrt-v4's `Texture "t" "spectrum" "imagemap"`: the file resolved beside the scene, uscale,
// vscale, udelta, vdelta and wrap carried over; a PNG is decoded from sRGB.
TEST(ImageTexture, PbrtImagemapBecomesAnImageTexture) {
  const test::TempDir dir;
  RgbImage png(2, 1);
  png.at(0, 0) = Rgb(1.0f, 0.0f, 0.0f);
  png.at(1, 0) = Rgb(0.0f, 0.0f, 1.0f);
  write_png(png, dir.file("rb.png"));
  test::write_bytes(dir.file("scene.pbrt"), R"(LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
Texture "rb" "spectrum" "imagemap" "string filename" "rb.png" "float uscale" 2
  "float vdelta" 0.5 "string wrap" "clamp"
Material "diffuse" "texture reflectance" "rb"
Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]
  "point2 uv" [0 0 1 0 0 1]
)");
  const SceneDesc desc = load_scene(dir.file("scene.pbrt"));
  ASSERT_FALSE(desc.materials.empty());
  const MaterialDesc* textured = nullptr;
  for (const MaterialDesc& m : desc.materials)
    if (m.params.get_json("albedo") && m.params.get_json("albedo")->is_object()) textured = &m;
  ASSERT_NE(textured, nullptr);
  const nlohmann::json& albedo = *textured->params.get_json("albedo");
  EXPECT_EQ(albedo["type"], "image");
  EXPECT_EQ(albedo["wrap"], "clamp");
  EXPECT_EQ(albedo["scale"], nlohmann::json::array({2.0, 1.0}));
  EXPECT_EQ(albedo["offset"], nlohmann::json::array({0.0, 0.5}));
  const auto material = make_material(textured->params);
  SurfaceInteraction si;
  MaterialScratch scratch;
  si.uv = {0.1f, 0.2f};  // s = 0.2: the red pixel's half, clamped
  expect_near(material->at(si, scratch).albedo(), Rgb(1.0f, 0.0f, 0.0f), 1e-5f);
  si.uv = {0.45f, 0.2f};  // s = 0.9: the blue pixel
  expect_near(material->at(si, scratch).albedo(), Rgb(0.0f, 0.0f, 1.0f), 1e-5f);
}

}  // namespace
}  // namespace penumbra
