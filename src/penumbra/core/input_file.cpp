#include "penumbra/core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "penumbra/core/error.h"

namespace penumbra {
namespace {

// Closes a descriptor when it goes out of scope.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string file_type_name(unsigned mode) {
  if (S_ISREG(mode)) return "";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  return "not a regular file";
}

std::string read_input_file(const std::string& path, std::uint64_t max_bytes) {
  // Refuse special files by name first: opening a FIFO for reading blocks until a writer comes.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    throw InputError(path, "", std::string("cannot open file: ") + std::strerror(errno));
  }
  const auto refuse_kind = [&](const struct stat& s) {
    const std::string kind = file_type_name(s.st_mode);
    if (!kind.empty()) throw InputError(path, "", "is " + kind + ", not a regular file");
  };
  refuse_kind(st);

  // Open without blocking (the name may have been replaced by a FIFO since), then check again.
  const Fd file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) {
    throw InputError(path, "", std::string("cannot open file: ") + std::strerror(errno));
  }
  if (::fstat(file.fd, &st) != 0) {
    throw InputError(path, "", std::string("cannot read file: ") + std::strerror(errno));
  }
  refuse_kind(st);
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes) {
    throw InputError(path, "",
                     "file of " + std::to_string(size) + " bytes is larger than the limit of " +
                         std::to_string(max_bytes) + " bytes");
  }

  // Read at most the size it had when opened: a file that grows meanwhile is cut there.
  std::string data(static_cast<size_t>(size), '\0');
  size_t done = 0;
  while (done < data.size()) {
    const ssize_t got = ::read(file.fd, data.data() + done, data.size() - done);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      throw InputError(path, "byte " + std::to_string(done),
                       std::string("cannot read file: ") + std::strerror(errno));
    }
    if (got == 0) break;  // the file shrank
    done += static_cast<size_t>(got);
  }
  data.resize(done);
  return data;
}

}  // namespace penumbra
