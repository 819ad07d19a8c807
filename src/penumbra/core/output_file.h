#pragma once
/// Writing an output file whole: the one place where penumbra's writers (images, tables, SVG,
/// saved solutions) hand bytes to the file system, so that a full disk or any other failed write
/// is seen, not left behind as a short file.
#include <string>
#include <string_view>

namespace penumbra {

/// Writes `bytes` to `path` (created with mode 0666 less the umask, or truncated), checking every
/// write, then flushes it to the disk (fsync) and closes it, checking both. Throws Error
/// "path: cannot write: REASON" (a full disk, a file-size limit, an I/O error) after which the
/// file may hold part of the bytes: callers write to a temporary file and rename it when this
/// returns (write_atomically in image/image_io.h).
void write_output_file(const std::string& path, std::string_view bytes);

/// What `path` is when it exists and is not a regular file, in words ("a directory", "a FIFO
/// (named pipe)", "a character device", ...; symbolic links followed); "" for a regular file or a
/// path that does not exist.
std::string special_file_kind(const std::string& path);

}  // namespace penumbra
