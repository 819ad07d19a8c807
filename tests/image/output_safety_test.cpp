/// Tests of writes that fail part-way (a full disk, a file-size limit) and of outputs penumbra
/// must not replace (devices, FIFOs, read-only files): the error names the file, no partial or
/// temporary file is left, and an existing output keeps its bytes.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "penumbra/core/error.h"
#include "penumbra/core/output_file.h"
#include "penumbra/image/exr.h"
#include "penumbra/image/image_io.h"
#include "penumbra/image/pfm.h"
#include "penumbra/image/png.h"
#include "temp_dir.h"

namespace penumbra {
namespace {

using test::read_bytes;
using test::TempDir;

/// An image of noise: it does not compress, so each format's bytes exceed a few KiB.
RgbImage noisy_image(int w, int h) {
  RgbImage image(w, h);
  uint32_t s = 12345;
  for (std::size_t i = 0; i < image.size(); ++i) {
    s = s * 1664525u + 1013904223u;
    image.data()[i] = Rgb(float(s >> 8) * 0x1p-24f, float((s >> 4) & 0xfff) / 4096.0f, 0.5f);
  }
  return image;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// Runs f in a child process whose files may not grow beyond `limit` bytes (RLIMIT_FSIZE; a
/// write beyond it fails with EFBIG once SIGXFSZ is ignored), returning the child's exit status:
/// 0 when f returned true.
int run_with_file_size_limit(rlim_t limit, const std::function<bool()>& f) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit rl{limit, limit};
    if (::setrlimit(RLIMIT_FSIZE, &rl) != 0) ::_exit(3);
    ::_exit(f() ? 0 : 1);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST(OutputFile, FullDeviceIsReportedNamingTheFile) {
  // /dev/full fails every write with ENOSPC: the disk-full case, without filling a disk.
  try {
    write_output_file("/dev/full", std::string(1000, 'x'));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/full: cannot write: No space left on device");
  }
}

TEST(OutputFile, WritesTheBytesExactly) {
  const TempDir dir;
  std::string bytes;
  for (int i = 0; i < 70000; ++i) bytes += char(i * 7);
  write_output_file(dir.file("b.bin"), bytes);
  EXPECT_EQ(read_bytes(dir.file("b.bin")), bytes);
}

TEST(OutputSafety, AWriteThatFailsPartWayKeepsTheOldFileAndLeavesNoTemporary) {
  const RgbImage image = noisy_image(64, 64);  // 12 KiB of PNG or more, 48 KiB of PFM or EXR
  for (const char* name : {"out.png", "out.exr", "out.pfm"}) {
    SCOPED_TRACE(name);
    const TempDir dir;
    const std::string path = dir.file(name);
    write_text(path, "the previous render");
    const int status = run_with_file_size_limit(4096, [&] {
      try {
        write_image(image, path);
        return false;  // the write should have failed
      } catch (const Error& e) {
        const std::string m = e.what();
        return m.find(path + ": cannot write: File too large") == 0;
      }
    });
    EXPECT_EQ(status, 0) << "the write did not fail with the file named and the reason";
    EXPECT_EQ(read_bytes(path), "the previous render");
    EXPECT_EQ(dir.entries().size(), 1u) << "a temporary file was left behind";
  }
}

TEST(OutputSafety, EveryFormatWritesWithinTheLimitItNeeds) {
  // The same child set-up succeeds when the limit is above the file's size: the test above fails
  // for the limit, not for the fork or the set-up.
  const RgbImage image = noisy_image(64, 64);
  for (const char* name : {"out.png", "out.exr", "out.pfm"}) {
    SCOPED_TRACE(name);
    const TempDir dir;
    const std::string path = dir.file(name);
    EXPECT_EQ(run_with_file_size_limit(1 << 20,
                                       [&] {
                                         write_image(image, path);
                                         return true;
                                       }),
              0);
    EXPECT_EQ(read_image(path).width(), 64);
  }
}

TEST(OutputSafety, EncodedBytesAreWhatTheWritersWrite) {
  const TempDir dir;
  const RgbImage image = noisy_image(9, 5);
  write_png(image, dir.file("a.png"));
  write_exr(image, dir.file("a.exr"));
  write_pfm(image, dir.file("a.pfm"));
  EXPECT_EQ(read_bytes(dir.file("a.png")), encode_png(image));
  EXPECT_EQ(read_bytes(dir.file("a.exr")), encode_exr(image));
  EXPECT_EQ(read_bytes(dir.file("a.pfm")), encode_pfm(image));
  // EXR through memory reads back bit-exact (the line-offset table written at the end).
  const RgbImage back = read_exr(dir.file("a.exr"));
  for (std::size_t i = 0; i < image.size(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(back.data()[i][c], image.data()[i][c]);
}

TEST(OutputSafety, ALinkToADeviceIsRefusedAndKept) {
  const TempDir dir;
  const std::string link = dir.file("out.png");
  std::filesystem::create_symlink("/dev/full", link);
  try {
    write_image(noisy_image(4, 4), link);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              link + ": cannot write: it is a character device, not a regular file");
  }
  EXPECT_THROW(check_writable(link), Error);
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  EXPECT_EQ(std::filesystem::read_symlink(link), "/dev/full");
  EXPECT_EQ(dir.entries().size(), 1u);
}

TEST(OutputSafety, AFifoIsRefusedWithoutBlocking) {
  const TempDir dir;
  const std::string fifo = dir.file("out.pfm");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  try {
    check_writable(fifo);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a FIFO (named pipe), not a regular file"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(write_image(noisy_image(4, 4), fifo), Error);
}

TEST(OutputSafety, AReadOnlyFileIsNotReplaced) {
  const TempDir dir;
  const std::string path = dir.file("keep.exr");
  write_text(path, "protected");
  ASSERT_EQ(::chmod(path.c_str(), 0444), 0);
  try {
    write_image(noisy_image(4, 4), path);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ": cannot write: the file exists and is read-only (not replaced)");
  }
  EXPECT_EQ(read_bytes(path), "protected");
  EXPECT_EQ(dir.entries().size(), 1u);
}

TEST(OutputSafety, ADirectoryIsRefused) {
  const TempDir dir;
  std::filesystem::create_directory(dir.file("x.png"));
  EXPECT_THROW(check_writable(dir.file("x.png")), Error);
  EXPECT_THROW(write_image(noisy_image(4, 4), dir.file("x.png")), Error);
  EXPECT_TRUE(std::filesystem::is_directory(dir.file("x.png")));
}

}  // namespace
}  // namespace penumbra
