/// Tests of PFM reading and writing: exactness, orientation, byte order, malformed input.
#include "penumbra/image/pfm.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

#include "temp_dir.h"

namespace penumbra {
namespace {

using test::read_bytes;
using test::TempDir;
using test::write_bytes;

// Four bytes of value in the given byte order.
std::string float_bytes(float value, bool little_endian) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  std::string out(4, '\0');
  for (int i = 0; i < 4; ++i) {
    const int shift = little_endian ? 8 * i : 8 * (3 - i);
    out[i] = static_cast<char>((bits >> shift) & 0xffu);
  }
  return out;
}

TEST(Pfm, RoundTripIsBitExact) {
  const TempDir dir;
  const float special[] = {0.0f,
                           -0.0f,
                           -1.5f,
                           1e-42f,  // denormal
                           std::numeric_limits<float>::min(),
                           std::numeric_limits<float>::max(),
                           -std::numeric_limits<float>::max(),
                           std::numeric_limits<float>::infinity(),
                           std::numeric_limits<float>::quiet_NaN(),
                           3.14159265f,
                           -1e30f,
                           1e-30f};
  RgbImage image(5, 3);
  for (std::size_t i = 0; i < image.size(); ++i) {
    image.data()[i] = Rgb(special[i % 12], special[(i + 5) % 12], static_cast<float>(i) * 0.1f);
  }
  write_pfm(image, dir.file("a.pfm"));
  const RgbImage back = read_pfm(dir.file("a.pfm"));
  ASSERT_EQ(back.width(), 5);
  ASSERT_EQ(back.height(), 3);
  EXPECT_EQ(std::memcmp(back.data(), image.data(), image.size() * sizeof(Rgb)), 0);
}

TEST(Pfm, HeaderIsLittleEndianColour) {
  const TempDir dir;
  write_pfm(RgbImage(7, 2), dir.file("h.pfm"));
  const std::string bytes = read_bytes(dir.file("h.pfm"));
  const std::string header = "PF\n7 2\n-1.0\n";
  ASSERT_EQ(bytes.size(), header.size() + 7 * 2 * 12);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
}

TEST(Pfm, TopRowIsStoredLast) {
  const TempDir dir;
  RgbImage image(2, 2);
  image.at(0, 0) = Rgb(1, 2, 3);  // top row
  image.at(1, 0) = Rgb(4, 5, 6);
  image.at(0, 1) = Rgb(7, 8, 9);  // bottom row
  image.at(1, 1) = Rgb(10, 11, 12);
  write_pfm(image, dir.file("o.pfm"));
  const std::string bytes = read_bytes(dir.file("o.pfm"));
  const std::size_t data = std::string("PF\n2 2\n-1.0\n").size();
  const float expected[] = {7, 8, 9, 10, 11, 12, 1, 2, 3, 4, 5, 6};
  ASSERT_EQ(bytes.size(), data + sizeof(expected));
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ(bytes.substr(data + 4 * i, 4), float_bytes(expected[i], true)) << i;
  }
}

TEST(Pfm, ReadsBigEndian) {
  const TempDir dir;
  std::string bytes = "PF\n2 1\n1.0\n";
  const float values[] = {1.0f, -2.5f, 1e-20f, 7.0f, 8.0f, 3e20f};
  for (float v : values) bytes += float_bytes(v, false);
  write_bytes(dir.file("be.pfm"), bytes);
  const RgbImage image = read_pfm(dir.file("be.pfm"));
  ASSERT_EQ(image.width(), 2);
  ASSERT_EQ(image.height(), 1);
  EXPECT_EQ(image.at(0, 0), Rgb(1.0f, -2.5f, 1e-20f));
  EXPECT_EQ(image.at(1, 0), Rgb(7.0f, 8.0f, 3e20f));
}

TEST(Pfm, ReadsGreyscaleAsRgb) {
  const TempDir dir;
  std::string bytes = "Pf\n2 2\n-4.0\n";
  for (float v : {1.0f, 2.0f, 3.0f, 4.0f}) bytes += float_bytes(v, true);
  write_bytes(dir.file("grey.pfm"), bytes);
  const RgbImage image = read_pfm(dir.file("grey.pfm"));
  ASSERT_EQ(image.width(), 2);
  ASSERT_EQ(image.height(), 2);
  EXPECT_EQ(image.at(0, 1), Rgb(1.0f));  // first in the file is bottom left
  EXPECT_EQ(image.at(1, 1), Rgb(2.0f));
  EXPECT_EQ(image.at(0, 0), Rgb(3.0f));
  EXPECT_EQ(image.at(1, 0), Rgb(4.0f));
}

TEST(Pfm, MalformedFilesThrowInputErrorWithFileAndOffset) {
  struct Case {
    const char* name;
    std::string bytes;
    const char* place;
  };
  const Case cases[] = {
      {"empty.pfm", "", "byte 0"},
      {"magic.pfm", "P6\n2 2\n255\n", "byte 0"},
      {"magic2.pfm", "PFX\n2 2\n-1.0\n", "byte 0"},
      {"width.pfm", "PF\nabc 2\n-1.0\n", "byte 3"},
      {"negative.pfm", "PF\n-2 2\n-1.0\n", "byte 3"},
      {"zero.pfm", "PF\n2 0\n-1.0\n", "byte 5"},
      {"overflow.pfm", "PF\n99999999999999999999 2\n-1.0\n", "byte 3"},
      {"intmax.pfm", "PF\n2147483648 1\n-1.0\n", "byte 3"},
      {"huge.pfm", "PF\n65536 65536\n-1.0\n", "byte 3"},
      {"scale.pfm", "PF\n2 2\nabc\n", "byte 7"},
      {"zeroscale.pfm", "PF\n2 2\n0.0\n", "byte 7"},
      {"header.pfm", "PF\n2 2", "byte 6"},
      {"long.pfm", "PF\n" + std::string(300, ' '), "byte 256"},
      {"truncated.pfm", "PF\n2 2\n-1.0\n" + std::string(40, '\0'), "byte 52"},
  };
  const TempDir dir;
  for (const Case& c : cases) {
    write_bytes(dir.file(c.name), c.bytes);
    try {
      read_pfm(dir.file(c.name));
      ADD_FAILURE() << c.name << " was accepted";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(dir.file(c.name)), std::string::npos) << message;
      EXPECT_NE(message.find(std::string(":") + c.place + ":"), std::string::npos) << message;
    }
  }
}

TEST(Pfm, MissingFileThrowsError) {
  const TempDir dir;
  EXPECT_THROW(read_pfm(dir.file("missing.pfm")), Error);
}

TEST(Pfm, EmptyImageIsNotWritten) {
  const TempDir dir;
  EXPECT_THROW(write_pfm(RgbImage(), dir.file("e.pfm")), Error);
}

}  // namespace
}  // namespace penumbra
