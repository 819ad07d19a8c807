#include "penumbra/core/output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "penumbra/core/error.h"
#include "penumbra/core/input_file.h"

namespace penumbra {
namespace {

[[noreturn]] void fail(const std::string& path, int error) {
  throw Error(path + ": cannot write: " + std::strerror(error));
}

}  // namespace

void write_output_file(const std::string& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail(path, errno);
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t put = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) {
      // A short write of 0 bytes is reported by the next call as the error itself (ENOSPC).
      const int error = put < 0 ? errno : ENOSPC;
      ::close(fd);
      fail(path, error);
    }
    done += size_t(put);
  }
  // Data that only reached the page cache can still fail on its way to the disk (a full or
  // removed network file system, delayed allocation): fsync reports it, and after a crash the
  // renamed file is complete, not empty.
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
    const int error = errno;
    ::close(fd);
    fail(path, error);
  }
  if (::close(fd) != 0 && errno != EINTR) fail(path, errno);
}

std::string special_file_kind(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return "";
  return file_type_name(st.st_mode);
}

}  // namespace penumbra
