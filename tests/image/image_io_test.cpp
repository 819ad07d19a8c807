/// Tests of format choice by extension and of atomic (temporary file, then rename) writes.
#include "penumbra/image/image_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "temp_dir.h"

namespace penumbra {
namespace {

using test::read_bytes;
using test::TempDir;

RgbImage test_image() {
  RgbImage image(6, 4);
  for (std::size_t i = 0; i < image.size(); ++i) {
    image.data()[i] = Rgb(0.01f * static_cast<float>(i), 0.5f, 2.0f);
  }
  return image;
}

TEST(ImageIo, FormatIsChosenByExtensionInAnyCase) {
  EXPECT_EQ(image_format_for("a/b.png"), ImageFormat::kPng);
  EXPECT_EQ(image_format_for("x.PnG"), ImageFormat::kPng);
  EXPECT_EQ(image_format_for("x.EXR"), ImageFormat::kExr);
  EXPECT_EQ(image_format_for("dir.png/x.pfm"), ImageFormat::kPfm);
}

TEST(ImageIo, WriteImagePicksFormatByExtension) {
  const TempDir dir;
  const RgbImage image = test_image();
  write_image(image, dir.file("a.PNG"));
  write_image(image, dir.file("a.exr"));
  write_image(image, dir.file("a.Pfm"));
  EXPECT_EQ(read_bytes(dir.file("a.PNG")).substr(0, 4), "\x89PNG");
  EXPECT_EQ(read_bytes(dir.file("a.exr")).substr(0, 4), "\x76\x2f\x31\x01");
  EXPECT_EQ(read_bytes(dir.file("a.Pfm")).substr(0, 3), "PF\n");
  // Float formats read back exactly, PNG to within 8-bit precision after clamping.
  EXPECT_EQ(read_image(dir.file("a.exr")), image);
  EXPECT_EQ(read_image(dir.file("a.Pfm")), image);
  const RgbImage png = read_image(dir.file("a.PNG"));
  ASSERT_EQ(png.width(), image.width());
  EXPECT_NEAR(png.at(5, 3).r, image.at(5, 3).r, 0.004f);
  EXPECT_EQ(png.at(5, 3).b, 1.0f);
}

TEST(ImageIo, UnknownExtensionIsRejectedListingValidOnes) {
  const TempDir dir;
  for (const char* name : {"a.jpg", "noextension", "a.png.bak"}) {
    try {
      write_image(test_image(), dir.file(name));
      ADD_FAILURE() << name << " accepted";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(name), std::string::npos) << message;
      for (const char* ext : {".png", ".exr", ".pfm"}) {
        EXPECT_NE(message.find(ext), std::string::npos) << message;
      }
    }
    EXPECT_THROW(read_image(dir.file(name)), Error);
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(ImageIo, WriteLeavesNoTemporaryFile) {
  const TempDir dir;
  write_image(test_image(), dir.file("out.exr"));
  write_image(test_image(), dir.file("out.exr"));  // replacing an existing file
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.exr"});
}

TEST(ImageIo, WriteIntoMissingDirectoryThrowsNamingTarget) {
  const TempDir dir;
  const std::string path = dir.file("missing/out.png");
  try {
    write_image(test_image(), path);
    FAIL() << "write succeeded";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path + ":"), std::string::npos) << message;
    EXPECT_EQ(message.find(".tmp-"), std::string::npos) << message;
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(ImageIo, FailedWriteLeavesTargetUntouched) {
  const TempDir dir;
  for (const char* name : {"keep.png", "keep.exr", "keep.pfm"}) {
    test::write_bytes(dir.file(name), "previous render");
    EXPECT_THROW(write_image(RgbImage(), dir.file(name)), Error);  // empty images are refused
    EXPECT_EQ(read_bytes(dir.file(name)), "previous render");
  }
  EXPECT_EQ(dir.entries().size(), 3u);
}

TEST(ImageIo, InterruptedWriteRemovesTemporaryAndKeepsTarget) {
  const TempDir dir;
  const std::string path = dir.file("target.bin");
  test::write_bytes(path, "old");
  std::string seen_temp;
  EXPECT_THROW(write_atomically(path,
                                [&](const std::string& temp) {
                                  seen_temp = temp;
                                  std::ofstream(temp) << "half a fi";
                                  throw std::runtime_error("interrupted");
                                }),
               std::runtime_error);
  EXPECT_EQ(std::filesystem::path(seen_temp).parent_path(), dir.path());
  EXPECT_EQ(read_bytes(path), "old");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"target.bin"});
}

TEST(ImageIo, FailedRenameRemovesTemporary) {
  const TempDir dir;
  // The target is a non-empty directory, so renaming a file onto it fails.
  std::filesystem::create_directories(dir.path() / "busy.pfm" / "inside");
  EXPECT_THROW(write_image(test_image(), dir.file("busy.pfm")), Error);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"busy.pfm"});
  EXPECT_TRUE(std::filesystem::is_directory(dir.path() / "busy.pfm" / "inside"));
}

}  // namespace
}  // namespace penumbra
