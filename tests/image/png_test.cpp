/// Tests of PNG writing (8-bit sRGB encoding, clamping, exposure) and reading.
#include "penumbra/image/png.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <vector>

#include "penumbra/image/tone_map.h"
#include "temp_dir.h"

namespace penumbra {
namespace {

using test::TempDir;

// The 8-bit RGB codes of a PNG, read with libpng's simplified API (no conversion).
std::vector<png_byte> raw_rgb(const std::string& path, int* width, int* height) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  EXPECT_NE(png_image_begin_read_from_file(&image, path.c_str()), 0) << image.message;
  image.format = PNG_FORMAT_RGB;
  std::vector<png_byte> bytes(PNG_IMAGE_SIZE(image));
  EXPECT_NE(png_image_finish_read(&image, nullptr, bytes.data(), 0, nullptr), 0) << image.message;
  *width = static_cast<int>(image.width);
  *height = static_cast<int>(image.height);
  return bytes;
}

TEST(Png, EncodesKnownValues) {
  const TempDir dir;
  RgbImage image(3, 1);
  image.at(0, 0) = Rgb(0.0f, 1.0f, 0.5f);
  image.at(1, 0) = Rgb(2.0f, -1.0f, std::nanf(""));
  image.at(2, 0) = Rgb(0.001f, 0.2f, 0.8f);
  write_png(image, dir.file("k.png"));
  int width = 0, height = 0;
  const std::vector<png_byte> bytes = raw_rgb(dir.file("k.png"), &width, &height);
  ASSERT_EQ(width, 3);
  ASSERT_EQ(height, 1);
  // 0.001 -> 12.92 * 0.001 * 255 = 3.29; 0.2 -> 0.4845 * 255 = 123.5...; 0.8 -> 0.9063 * 255.
  const std::vector<png_byte> expected = {0, 255, 188, 255, 0, 0, 3, 124, 231};
  EXPECT_EQ(bytes, expected);
}

TEST(Png, ExposureScalesBeforeEncoding) {
  const TempDir dir;
  write_png(RgbImage(1, 1, Rgb(0.25f, 0.5f, 0.0f)), dir.file("e.png"), 2.0f);
  int width = 0, height = 0;
  const std::vector<png_byte> bytes = raw_rgb(dir.file("e.png"), &width, &height);
  EXPECT_EQ(bytes, (std::vector<png_byte>{188, 255, 0}));
}

TEST(Png, TopRowIsFirstAndFileIsTaggedSrgb) {
  const TempDir dir;
  RgbImage image(1, 2);
  image.at(0, 0) = Rgb(1.0f);
  write_png(image, dir.file("t.png"));
  int width = 0, height = 0;
  const std::vector<png_byte> bytes = raw_rgb(dir.file("t.png"), &width, &height);
  EXPECT_EQ(bytes, (std::vector<png_byte>{255, 255, 255, 0, 0, 0}));
  EXPECT_NE(test::read_bytes(dir.file("t.png")).find("sRGB"), std::string::npos);
}

TEST(Png, ReadDecodesToLinear) {
  const TempDir dir;
  RgbImage image(4, 2);
  for (std::size_t i = 0; i < image.size(); ++i) {
    image.data()[i] = Rgb(static_cast<float>(i) / 8.0f, 0.5f, 1.0f);
  }
  write_png(image, dir.file("r.png"));
  const RgbImage back = read_png(dir.file("r.png"));
  ASSERT_EQ(back.width(), 4);
  ASSERT_EQ(back.height(), 2);
  for (std::size_t i = 0; i < image.size(); ++i) {
    const Rgb expected = image.data()[i];
    for (int c = 0; c < 3; ++c) {
      // Exactly the decoded 8-bit code, and within half a code step of the original.
      const float code = srgb_encode_8bit(expected[c]);
      EXPECT_EQ(back.data()[i][c], srgb_decode(code / 255.0f)) << i;
      EXPECT_NEAR(back.data()[i][c], expected[c], 0.004f) << i;
    }
  }
}

TEST(Png, GarbageFileThrowsInputErrorNamingFile) {
  const TempDir dir;
  test::write_bytes(dir.file("bad.png"), "\x89PNG but not really a PNG file");
  try {
    read_png(dir.file("bad.png"));
    FAIL() << "garbage accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("bad.png")), std::string::npos) << e.what();
  }
}

TEST(Png, WriteIntoMissingDirectoryThrowsError) {
  const TempDir dir;
  EXPECT_THROW(write_png(RgbImage(2, 2), dir.file("missing/a.png")), Error);
}

}  // namespace
}  // namespace penumbra
