// The image readers' in-memory entry points (what the fuzz targets feed): the same pixels as the
// path readers, and clear errors for empty, truncated, oversized and special inputs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "penumbra/core/error.h"
#include "penumbra/image/exr.h"
#include "penumbra/image/image_io.h"
#include "penumbra/image/pfm.h"
#include "penumbra/image/png.h"
#include "temp_dir.h"

namespace penumbra {
namespace {

using test::TempDir;

RgbImage gradient() {
  RgbImage img(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) img.at(x, y) = Rgb(0.1f * x, 0.2f * y, 0.5f);
  return img;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <class Read>
std::string message_of(Read&& read) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

void expect_same(const RgbImage& a, const RgbImage& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(a.data()[i][c], b.data()[i][c]);
}

TEST(DecodeMemory, EachFormatDecodesTheBytesItsPathReaderReads) {
  TempDir dir;
  for (const char* ext : {".pfm", ".png", ".exr"}) {
    const std::string file = dir.file(std::string("g") + ext);
    write_image(gradient(), file);
    const std::string bytes = slurp(file);
    const RgbImage from_memory = std::string(ext) == ".pfm"   ? decode_pfm(bytes, file)
                                 : std::string(ext) == ".png" ? decode_png(bytes, file)
                                                              : decode_exr(bytes, file);
    expect_same(from_memory, read_image(file));
  }
}

TEST(DecodeMemory, EmptyAndTruncatedInputsAreInputErrors) {
  EXPECT_EQ(message_of([] { decode_png("", "e.png"); }), "e.png: empty file (0 bytes), not a PNG");
  EXPECT_EQ(message_of([] { decode_exr("", "e.exr"); }), "e.exr: empty file (0 bytes), not an EXR");
  EXPECT_NE(message_of([] { decode_pfm("", "e.pfm"); }).find("e.pfm:byte 0"), std::string::npos);
  TempDir dir;
  write_image(gradient(), dir.file("g.png"));
  const std::string png = slurp(dir.file("g.png"));
  const std::string m = message_of([&] { decode_png(png.substr(0, png.size() / 2), "t.png"); });
  EXPECT_EQ(m.rfind("t.png:byte ", 0), 0u) << m;  // the chunk the file ends in
  EXPECT_NE(m.find("bytes, but only"), std::string::npos) << m;
}

TEST(DecodeMemory, PfmTrailingDataIsAnError) {
  const std::string pfm = std::string("Pf\n1 1\n-1.0\n") + std::string(4, '\0') + "junk";
  EXPECT_EQ(message_of([&] { decode_pfm(pfm, "t.pfm"); }),
            "t.pfm:byte 16: 4 bytes of trailing data after the pixel data");
  EXPECT_EQ(decode_pfm(pfm.substr(0, 16), "t.pfm").width(), 1);
}

TEST(DecodeMemory, PixelLimitIsCheckedBeforeAllocating) {
  const std::string pfm = "PF\n4096 4096\n-1.0\n";  // claims 4096 x 4096, holds nothing
  EXPECT_NE(message_of([&] { decode_pfm(pfm, "big.pfm", 1 << 20); }).find("more than the limit"),
            std::string::npos);
  TempDir dir;
  write_image(gradient(), dir.file("g.png"));
  EXPECT_NE(message_of([&] {
              decode_png(slurp(dir.file("g.png")), "g.png", 14);
            }).find("larger than the limit of 14"),
            std::string::npos);
}

TEST(DecodeMemory, SpecialFilesAreRefusedBeforeReading) {
  TempDir dir;
  std::filesystem::create_directory(dir.file("d.exr"));
  EXPECT_NE(message_of([&] { read_image(dir.file("d.exr")); }).find("is a directory"),
            std::string::npos);
}

// Fuzz finding (fuzz_png): a 130-byte file whose iTXt chunk claims 640 MB was allocated and
// cleared by libpng before the data was found missing (a 14 s timeout under ASan).
TEST(DecodeMemory, FuzzPngHugeTextChunkFailsFast) {
  const std::string file = std::string(PENUMBRA_TEST_DATA) + "/fuzz/png-itxt-640mb-chunk.png";
  const std::string m = message_of([&] { decode_png(slurp(file), "f.png"); });
  EXPECT_EQ(m.rfind("f.png:byte 33: chunk 'iTXt' declares 640034342 bytes, but only 89 follow", 0),
            0u)
      << m;
}

// Fuzz finding (fuzz_exr): a 468-byte file with an attribute that declares 1.6 GB made OpenEXR
// allocate it before reading; the headers are now checked against the file's size first.
TEST(DecodeMemory, FuzzExrAttributeLargerThanTheFileIsRefused) {
  const std::string file = std::string(PENUMBRA_TEST_DATA) + "/fuzz/exr-1600mb-attribute.exr";
  const std::string m = message_of([&] { decode_exr(slurp(file), "f.exr"); });
  EXPECT_NE(m.find("f.exr:byte "), std::string::npos) << m;
  EXPECT_NE(m.find("bytes, but only"), std::string::npos) << m;
}

// Fuzz finding (fuzz_png): a 74-byte file whose tEXt chunk claims 1.2 GB; libpng allocated it
// (the chunk malloc limit does not cover text chunks). The chunks are now walked first.
TEST(DecodeMemory, FuzzPngChunkLongerThanTheFileIsRefused) {
  const std::string file = std::string(PENUMBRA_TEST_DATA) + "/fuzz/png-text-1200mb-chunk.png";
  const std::string m = message_of([&] { decode_png(slurp(file), "f.png"); });
  EXPECT_NE(m.find("f.png:byte 33: chunk 'tEXt' declares 1256361531 bytes, but only"),
            std::string::npos)
      << m;
}

// Fuzz finding (fuzz_exr): a channel list that runs past its declared size made OpenEXR read
// the rest of the header out of step, into an unknown attribute of 1.7 GB.
TEST(DecodeMemory, FuzzExrChannelListOverrunIsRefused) {
  const std::string file = std::string(PENUMBRA_TEST_DATA) + "/fuzz/exr-channel-list-overrun.exr";
  const std::string m = message_of([&] { decode_exr(slurp(file), "f.exr"); });
  EXPECT_NE(m.find("f.exr:byte "), std::string::npos) << m;
}

// Fuzz finding (fuzz_exr): tiles of 2 x 134217730 pixels made OpenEXR's setFrameBuffer allocate
// a row of tiles of gigabytes (a timeout). Tile sizes are now bounded by the pixel limit.
TEST(DecodeMemory, FuzzExrHugeTileIsRefused) {
  const std::string file = std::string(PENUMBRA_TEST_DATA) + "/fuzz/exr-huge-tile.exr";
  const std::string m = message_of([&] { decode_exr(slurp(file), "f.exr"); });
  EXPECT_NE(m.find("f.exr:byte 295: tiles of 2 x 134217730 pixels"), std::string::npos) << m;
}

TEST(DecodeMemory, ExrDataWindowAboveTheLimitIsRefusedBeforeOpenExr) {
  TempDir dir;
  write_image(gradient(), dir.file("g.exr"));
  const std::string m = message_of([&] { decode_exr(slurp(dir.file("g.exr")), "g.exr", 14); });
  EXPECT_NE(m.find("data window of 5 x 3 pixels is empty or larger than the limit of 14"),
            std::string::npos)
      << m;
  EXPECT_NE(message_of([] { decode_exr("P3 not an exr", "n.exr"); }).find("bad magic"),
            std::string::npos);
}

}  // namespace
}  // namespace penumbra
