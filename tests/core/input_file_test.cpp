// Reading input files: only regular files, read up to their size; text checks for messages.
#include "penumbra/core/input_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "penumbra/core/error.h"
#include "penumbra/core/text_escape.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

/// A fresh directory removed at the end of the test.
struct TempDir {
  fs::path path =
      fs::temp_directory_path() / ("penumbra-input-" + std::to_string(::getpid()) + "-" +
                                   std::to_string(reinterpret_cast<uintptr_t>(this)));
  TempDir() { fs::create_directories(path); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string error_of(const std::string& path) {
  try {
    read_input_file(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(InputFile, ReadsARegularFileWhole) {
  TempDir dir;
  const std::string file = (dir.path / "a.txt").string();
  std::ofstream(file, std::ios::binary) << std::string("one\0two", 7);
  EXPECT_EQ(read_input_file(file), std::string("one\0two", 7));
}

TEST(InputFile, MissingFileSaysCannotOpen) {
  EXPECT_NE(error_of("/nonexistent/penumbra.obj").find("/nonexistent/penumbra.obj: cannot open"),
            std::string::npos);
}

TEST(InputFile, DirectoryIsRefused) {
  TempDir dir;
  const std::string message = error_of(dir.path.string());
  EXPECT_NE(message.find("is a directory, not a regular file"), std::string::npos) << message;
}

TEST(InputFile, DevZeroIsRefusedBeforeReading) {
  const std::string message = error_of("/dev/zero");
  EXPECT_NE(message.find("/dev/zero: is a character device, not a regular file"), std::string::npos)
      << message;
}

TEST(InputFile, FifoIsRefusedWithoutBlocking) {
  TempDir dir;
  const std::string fifo = (dir.path / "pipe.json").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string message = error_of(fifo);  // would block forever if it were opened
  EXPECT_NE(message.find("is a FIFO (named pipe), not a regular file"), std::string::npos)
      << message;
}

TEST(InputFile, FileAboveTheLimitIsRefused) {
  TempDir dir;
  const std::string file = (dir.path / "big.ply").string();
  std::ofstream(file) << std::string(100, 'x');
  try {
    read_input_file(file, 99);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("100 bytes is larger than the limit of 99"),
              std::string::npos)
        << e.what();
  }
}

TEST(TextEscape, ControlBytesAreEscapedAndLongTextIsCut) {
  EXPECT_EQ(escape_for_message(std::string("a\0b\x1b[31m\x7f", 9)), "a\\x00b\\x1b[31m\\x7f");
  EXPECT_EQ(escape_for_message("caf\xc3\xa9"), "caf\xc3\xa9");  // UTF-8 is kept
  EXPECT_EQ(escape_for_message("\xff\xc3"), "\\xff\\xc3");      // invalid UTF-8 is not
  EXPECT_EQ(escape_for_message("\xc2\x85"), "\\xc2\\x85");      // nor a C1 control
  EXPECT_EQ(escape_for_message(std::string(100, 'x'), 40),
            std::string(40, 'x') + "... (100 bytes)");
}

TEST(TextEscape, Utf16AndBinaryDataAreRecognised) {
  EXPECT_EQ(describe_non_text(std::string_view("\xff\xfev\0 \0", 6)).value_or(""),
            "UTF-16 text: convert to UTF-8");
  EXPECT_EQ(describe_non_text(std::string("v\0 \0", 4)).value_or(""),
            "UTF-16 text: convert to UTF-8");
  EXPECT_EQ(describe_non_text(std::string("\xff\xfe\0\0", 4)).value_or(""),
            "UTF-32 text: convert to UTF-8");
  EXPECT_EQ(describe_non_text(std::string("v 1 2 3\n\x01\x02", 10)).value_or(""),
            "binary data at byte 8 (0x01): expected text");
  EXPECT_FALSE(describe_non_text("v 1 2 3\r\n\tf 1 2 3\f\v").has_value());
}

TEST(InputError, MessagePartsNeverCarryRawControlBytes) {
  const InputError e("a.json", "/render/\x01key", "unknown key '\x1b[2J'");
  EXPECT_STREQ(e.what(), "a.json:/render/\\x01key: unknown key '\\x1b[2J'");
}

}  // namespace
}  // namespace penumbra
