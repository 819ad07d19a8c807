// The JPEG reader (libjpeg): known pixel values within JPEG's error, every libjpeg error an
// InputError naming the source (never libjpeg's exit()), the pixel limit before decoding, and
// .jpg/.jpeg files through read_image and decode_image.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "penumbra/core/error.h"
#include "penumbra/image/image_io.h"
#include "penumbra/image/jpeg.h"
#include "penumbra/image/png.h"
#include "penumbra/image/tone_map.h"
#include "temp_dir.h"

namespace penumbra {
namespace {

// 8-bit sRGB code -> the linear value the image holds for it.
Rgb linear(int r, int g, int b) {
  return Rgb(srgb_decode(r / 255.0f), srgb_decode(g / 255.0f), srgb_decode(b / 255.0f));
}

// A 16 x 16 image of four flat 8 x 8 blocks (one JPEG block each: only their DC coefficients are
// non-zero, so quality 100 keeps them to the rounding of the colour conversion).
const int kCodes[4][3] = {{200, 40, 90}, {10, 220, 130}, {128, 128, 128}, {250, 250, 5}};
RgbImage blocks() {
  RgbImage img(16, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const int* c = kCodes[(y / 8) * 2 + x / 8];
      img.at(x, y) = linear(c[0], c[1], c[2]);
    }
  return img;
}

std::string message_of(const std::string& bytes, std::size_t max_pixels = kMaxImagePixels) {
  try {
    decode_jpeg(bytes, "bad.jpg", max_pixels);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Jpeg, FlatBlocksDecodeToTheirColoursWithinJpegError) {
  const RgbImage decoded = decode_jpeg(encode_jpeg(blocks(), 100), "blocks.jpg");
  ASSERT_EQ(decoded.width(), 16);
  ASSERT_EQ(decoded.height(), 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const int* c = kCodes[(y / 8) * 2 + x / 8];
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(srgb_encode_8bit(decoded.at(x, y)[ch]), c[ch], 2)
            << "pixel " << x << ", " << y << " channel " << ch;
    }
  // The values are linear (decoded from sRGB), not the codes / 255.
  EXPECT_NEAR(decoded.at(4, 12)[0], srgb_decode(128 / 255.0f), 0.01f);
  EXPECT_LT(decoded.at(4, 12)[0], 0.3f);
}

TEST(Jpeg, ASmoothGradientStaysCloseAtQuality90) {
  RgbImage img(24, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) img.at(x, y) = linear(10 * x, 15 * y, 100);
  const RgbImage decoded = decode_jpeg(encode_jpeg(img, 90), "gradient.jpg");
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x)
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(srgb_encode_8bit(decoded.at(x, y)[ch]), srgb_encode_8bit(img.at(x, y)[ch]), 8);
}

TEST(Jpeg, CorruptTruncatedAndForeignBytesAreInputErrorsNamingTheSource) {
  EXPECT_EQ(message_of(""), "bad.jpg: empty file (0 bytes), not a JPEG");
  EXPECT_EQ(message_of(encode_png(blocks())).rfind("bad.jpg:byte 0: not a JPEG", 0), 0u);
  EXPECT_EQ(
      message_of(std::string("\xFF\xD8\xFF\x01garbage", 11)).rfind("bad.jpg: invalid JPEG: ", 0),
      0u)
      << message_of(std::string("\xFF\xD8\xFF\x01garbage", 11));
  // Every prefix: an InputError or an image, never exit() or a crash (the scan data may be cut:
  // libjpeg then fills the rest and warns, which is accepted).
  const std::string good = encode_jpeg(blocks(), 95);
  int errors = 0;
  for (std::size_t n = 1; n < good.size(); n += 3) {
    try {
      const RgbImage img = decode_jpeg(good.substr(0, n), "cut.jpg");
      EXPECT_EQ(img.width(), 16);
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("cut.jpg", 0), 0u) << e.what();
      ++errors;
    }
  }
  EXPECT_GT(errors, 10);  // every prefix without the whole header
  // Flipped bytes in the header: errors or images, never a crash.
  for (std::size_t i = 2; i < 200 && i < good.size(); ++i) {
    std::string bad = good;
    bad[i] = char(bad[i] ^ 0x5A);
    try {
      decode_jpeg(bad, "flip.jpg");
    } catch (const InputError&) {
    }
  }
}

TEST(Jpeg, ImagesAboveThePixelLimitAreRefusedBeforeDecoding) {
  const std::string bytes = encode_jpeg(blocks(), 90);
  EXPECT_NE(message_of(bytes, 255).find("JPEG of 16 x 16 pixels is larger than the limit of 255"),
            std::string::npos);
  EXPECT_EQ(message_of(bytes, 256), "(no error)");
}

TEST(Jpeg, ReadImageAndDecodeImageReadJpegFiles) {
  test::TempDir dir;
  const std::string bytes = encode_jpeg(blocks(), 100);
  for (const char* name : {"a.jpg", "b.JPEG"}) {
    std::ofstream(dir.file(name), std::ios::binary) << bytes;
    EXPECT_EQ(read_image(dir.file(name)), decode_jpeg(bytes, name)) << name;
  }
  EXPECT_EQ(decode_image(bytes, "x"), decode_jpeg(bytes, "x"));
  const std::string png = encode_png(blocks());
  EXPECT_EQ(decode_image(png, "x"), decode_png(png, "x"));
  EXPECT_THROW(decode_image("GIF89a", "x.gif"), InputError);
}

}  // namespace
}  // namespace penumbra
