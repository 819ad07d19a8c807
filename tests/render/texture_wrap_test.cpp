/// Image textures' mirrored-repeat wrap (glTF's MIRRORED_REPEAT), a wrap mode per axis and the
/// colour factor, against lookups worked out by hand; their JSON syntax; JPEG image files.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "../image/temp_dir.h"
#include "penumbra/core/error.h"
#include "penumbra/image/jpeg.h"
#include "penumbra/render/material/material_registry.h"
#include "penumbra/render/surface_interaction.h"
#include "penumbra/render/texture/texture.h"
#include "penumbra/render/texture/texture_params.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

using W = Texture::Wrap;

// A 4 x 1 image: pixel x = (x, 10 x, 0.5) / 40 (row 0 only: t does not matter along y).
std::shared_ptr<const RgbImage> row_image() {
  auto image = std::make_shared<RgbImage>(4, 1);
  for (int x = 0; x < 4; ++x) image->at(x, 0) = Rgb(x / 40.0f, x / 4.0f, 0.0125f);
  return image;
}

// A 1 x 4 image: pixel y (row 0 at the top) = (y / 4, 0, 0).
std::shared_ptr<const RgbImage> column_image() {
  auto image = std::make_shared<RgbImage>(1, 4);
  for (int y = 0; y < 4; ++y) image->at(0, y) = Rgb(y / 4.0f, 0.0f, 0.0f);
  return image;
}

Rgb at(const Texture& t, float u, float v) {
  return t.eval(TextureQuery{{}, {u, v}});
}

void expect_near(Rgb a, Rgb b, float tol = 1e-6f) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << "channel " << c;
}

TEST(TextureWrap, MirrorReflectsEveryOtherCopyOfTheImage) {
  const auto img = row_image();
  const Texture mirror = Texture::image(img, {1, 1}, {0, 0}, W::kMirror);
  const Texture repeat = Texture::image(img, {1, 1}, {0, 0}, W::kRepeat);
  // Pixel centres of copy 0 at s = (x + 0.5) / 4; copy 1 (s in [1, 2)) holds pixel 3 - x at
  // s = 1 + (x + 0.5) / 4; copy -1 (s in [-1, 0)) is mirrored too; copy 2 is copy 0 again.
  for (int x = 0; x < 4; ++x) {
    const float s = (x + 0.5f) / 4;
    expect_near(at(mirror, s, 0.5f), img->at(x, 0));
    expect_near(at(mirror, 1 + s, 0.5f), img->at(3 - x, 0));
    expect_near(at(mirror, -1 + s, 0.5f), img->at(3 - x, 0));
    expect_near(at(mirror, 2 + s, 0.5f), img->at(x, 0));
    expect_near(at(mirror, -2 + s, 0.5f), img->at(x, 0));
  }
  // At the seam s = 1 both sides are pixel 3: no blend with pixel 0 as repeat has.
  expect_near(at(mirror, 1.0f, 0.5f), img->at(3, 0));
  expect_near(at(mirror, 0.0f, 0.5f), img->at(0, 0));
  expect_near(at(repeat, 1.0f, 0.5f), (img->at(3, 0) + img->at(0, 0)) * 0.5f);
  // A quarter of the way from the first centre of copy 1 (pixel 3) to its second (pixel 2).
  expect_near(at(mirror, 1 + 0.25f / 4 + 0.125f, 0.5f),
              img->at(3, 0) * 0.75f + img->at(2, 0) * 0.25f);
  // Far from the origin the pattern holds (period 2).
  expect_near(at(mirror, 1000 + 1 + 1.5f / 4, 0.5f), img->at(2, 0), 1e-4f);
}

TEST(TextureWrap, EachAxisHasItsOwnMode) {
  const auto col = column_image();
  // s repeats (one column: constant), t mirrors: t in (1, 2) shows the image upside down.
  const Texture t = Texture::image(col, {1, 1}, {0, 0}, W::kRepeat, W::kMirror, Rgb(1.0f));
  for (int y = 0; y < 4; ++y) {
    const float v = 1 - (y + 0.5f) / 4;  // the centre of row y
    expect_near(at(t, 0.3f, v), col->at(0, y));
    expect_near(at(t, 5.7f, 1 + (1 - v)), col->at(0, y));  // mirrored copy above
  }
  // Clamp along s, black along t.
  const auto row = row_image();
  const Texture cb = Texture::image(row, {1, 1}, {0, 0}, W::kClamp, W::kBlack, Rgb(1.0f));
  expect_near(at(cb, -3.0f, 0.5f), row->at(0, 0));
  expect_near(at(cb, 7.0f, 0.5f), row->at(3, 0));
  expect_near(at(cb, 0.375f, 1.5f), Rgb(0.0f));
  expect_near(at(cb, 0.375f, -0.5f), Rgb(0.0f));
}

TEST(TextureWrap, FactorMultipliesEveryLookup) {
  const auto row = row_image();
  const Rgb f(0.5f, 0.25f, 1.0f);
  const Texture plain = Texture::image(row, {1, 1}, {0, 0}, W::kRepeat);
  const Texture scaled = Texture::image(row, {1, 1}, {0, 0}, W::kRepeat, W::kRepeat, f);
  for (float u : {0.1f, 0.33f, 0.9f, 1.7f}) {
    const Rgb p = at(plain, u, 0.5f), s = at(scaled, u, 0.5f);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(s[c], p[c] * f[c]) << u;
  }
}

// The JSON syntax: "wrap" one name or [s, t], "factor" a colour; JPEG files read by extension.
TEST(TextureWrap, JsonWrapPairFactorAndJpegFiles) {
  const test::TempDir dir;
  RgbImage img(16, 8, Rgb(0.2f, 0.6f, 0.4f));
  std::ofstream(dir.file("flat.jpg"), std::ios::binary) << encode_jpeg(img, 100);
  const auto material = [&](const std::string& albedo) {
    return make_material(
        SceneParams(nlohmann::json::parse(R"({"type": "diffuse", "albedo": )" + albedo + "}"),
                    "s.json", "/materials/m"));
  };
  const std::string file = "\"file\": \"" + dir.file("flat.jpg") + "\"";
  const auto m = material(R"({"type": "image", )" + file +
                          R"(, "wrap": ["mirror", "clamp"], "factor": [1, 0.5, 0]})");
  SurfaceInteraction si;
  MaterialScratch scratch;
  si.uv = {1.3f, -2.0f};
  expect_near(m->at(si, scratch).albedo(), Rgb(0.2f, 0.3f, 0.0f), 0.015f);
  const auto error_of = [&](const std::string& albedo) -> std::string {
    try {
      material(albedo);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error_of(R"({"type": "image", )" + file + R"(, "wrap": ["mirror", "spin"]})"),
            "s.json:/materials/m/albedo/wrap/1: unknown wrap 'spin' (valid: repeat, clamp, black, "
            "mirror)");
  EXPECT_EQ(error_of(R"({"type": "image", )" + file + R"(, "wrap": ["mirror"]})"),
            "s.json:/materials/m/albedo/wrap: expected 2 wrap modes [s, t], got 1");
  EXPECT_EQ(error_of(R"({"type": "image", )" + file + R"(, "factor": [1, 2, 0]})"),
            "s.json:/materials/m/albedo/factor: must lie in [0, 1]");
  std::ofstream(dir.file("bad.jpg"), std::ios::binary) << "\xFF\xD8\xFF\x01 not a jpeg";
  EXPECT_NE(error_of(R"({"type": "image", "file": ")" + dir.file("bad.jpg") + "\"}")
                .find("/materials/m/albedo/file: cannot read the texture: "),
            std::string::npos);
}

}  // namespace
}  // namespace penumbra
