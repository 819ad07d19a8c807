/// Tests of the Image container and the sRGB transfer curve.
#include "penumbra/image/image.h"

#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/image/tone_map.h"

namespace penumbra {
namespace {

TEST(Image, DefaultIsEmpty) {
  const Image<float> image;
  EXPECT_EQ(image.width(), 0);
  EXPECT_EQ(image.height(), 0);
  EXPECT_TRUE(image.empty());
}

TEST(Image, StorageIsRowMajorFromTheTop) {
  Image<int> image(3, 2);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) image.at(x, y) = 10 * y + x;
  }
  const int expected[] = {0, 1, 2, 10, 11, 12};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(image.data()[i], expected[i]);
  EXPECT_EQ(image.row(1), image.data() + 3);
}

TEST(Image, ResizeAndFillSetEveryPixel) {
  RgbImage image(2, 2, Rgb(1.0f));
  image.resize(4, 3, Rgb(2.0f));
  EXPECT_EQ(image.width(), 4);
  EXPECT_EQ(image.height(), 3);
  ASSERT_EQ(image.size(), 12u);
  for (std::size_t i = 0; i < image.size(); ++i) EXPECT_EQ(image.data()[i], Rgb(2.0f));
  image.fill(Rgb(0.5f, 0.25f, 0.125f));
  for (std::size_t i = 0; i < image.size(); ++i) {
    EXPECT_EQ(image.data()[i], Rgb(0.5f, 0.25f, 0.125f));
  }
}

TEST(Image, NegativeSizeThrowsError) {
  EXPECT_THROW(RgbImage(-1, 4), Error);
  RgbImage image;
  EXPECT_THROW(image.resize(4, -1), Error);
}

TEST(ToneMap, SrgbCurveHasKnownValues) {
  EXPECT_EQ(srgb_encode(0.0f), 0.0f);
  EXPECT_NEAR(srgb_encode(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(srgb_encode(0.5f), 0.735357f, 1e-5f);
  EXPECT_NEAR(srgb_encode(0.001f), 0.01292f, 1e-7f);  // linear segment
  // The two pieces meet at the breakpoint.
  EXPECT_NEAR(srgb_encode(0.0031308f), 0.04045f, 1e-5f);
}

TEST(ToneMap, DecodeInvertsEncode) {
  for (int i = 0; i <= 1000; ++i) {
    const float x = static_cast<float>(i) / 1000.0f;
    EXPECT_NEAR(srgb_decode(srgb_encode(x)), x, 2e-6f) << x;
  }
}

TEST(ToneMap, EightBitEncodingClampsAndRounds) {
  EXPECT_EQ(srgb_encode_8bit(0.0f), 0);
  EXPECT_EQ(srgb_encode_8bit(1.0f), 255);
  EXPECT_EQ(srgb_encode_8bit(0.5f), 188);
  EXPECT_EQ(srgb_encode_8bit(7.0f), 255);
  EXPECT_EQ(srgb_encode_8bit(-3.0f), 0);
  EXPECT_EQ(srgb_encode_8bit(std::nanf("")), 0);
  EXPECT_EQ(srgb_encode_8bit(INFINITY), 255);
}

}  // namespace
}  // namespace penumbra
