/// Tests of EXR reading and writing through OpenEXR.
#include "penumbra/image/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <gtest/gtest.h>

#include <vector>

#include "temp_dir.h"

namespace penumbra {
namespace {

using test::TempDir;

TEST(Exr, RoundTripIsFloatExact) {
  const TempDir dir;
  RgbImage image(17, 9);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      image.at(x, y) = Rgb(0.1f * x - 0.7f, 1e-30f * (y + 1), 1e30f / (x + y + 1));
    }
  }
  write_exr(image, dir.file("a.exr"));
  const RgbImage back = read_exr(dir.file("a.exr"));
  EXPECT_EQ(back, image);
}

TEST(Exr, FileHasZipCompressedFloatRgb) {
  const TempDir dir;
  write_exr(RgbImage(4, 3, Rgb(0.5f)), dir.file("c.exr"));
  Imf::InputFile file(dir.file("c.exr").c_str());
  EXPECT_EQ(file.header().compression(), Imf::ZIP_COMPRESSION);
  const Imath::Box2i window = file.header().dataWindow();
  EXPECT_EQ(window.max.x - window.min.x + 1, 4);
  EXPECT_EQ(window.max.y - window.min.y + 1, 3);
  for (const char* name : {"R", "G", "B"}) {
    const Imf::Channel* channel = file.header().channels().findChannel(name);
    ASSERT_NE(channel, nullptr) << name;
    EXPECT_EQ(channel->type, Imf::FLOAT) << name;
  }
}

TEST(Exr, ReadsHalfLuminanceWithOffsetWindow) {
  const TempDir dir;
  const std::string path = dir.file("y.exr");
  {
    // A 3 x 2 half-float "Y" file whose data window starts at (10, 20).
    const Imath::Box2i window({10, 20}, {12, 21});
    Imf::Header header(window, window);
    header.channels().insert("Y", Imf::Channel(Imf::HALF));
    std::vector<half> values = {0.0f, 0.5f, 1.0f, 2.0f, -4.0f, 0.25f};
    Imf::FrameBuffer frame;
    frame.insert("Y", Imf::Slice::Make(Imf::HALF, values.data(), window));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(2);
  }
  const RgbImage image = read_exr(path);
  ASSERT_EQ(image.width(), 3);
  ASSERT_EQ(image.height(), 2);
  EXPECT_EQ(image.at(1, 0), Rgb(0.5f));
  EXPECT_EQ(image.at(0, 1), Rgb(2.0f));
  EXPECT_EQ(image.at(1, 1), Rgb(-4.0f));
}

TEST(Exr, GarbageFileThrowsInputErrorNamingFile) {
  const TempDir dir;
  test::write_bytes(dir.file("bad.exr"), "this is not an OpenEXR file at all");
  try {
    read_exr(dir.file("bad.exr"));
    FAIL() << "garbage accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("bad.exr")), std::string::npos) << e.what();
  }
}

TEST(Exr, WriteIntoMissingDirectoryThrowsError) {
  const TempDir dir;
  const std::string path = dir.file("no/such/dir/a.exr");
  try {
    write_exr(RgbImage(2, 2), path);
    FAIL() << "write succeeded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra
