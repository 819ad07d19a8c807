#pragma once
/// Reading an input file whole: the one place where penumbra's readers (scene, meshes, images,
/// the 2D laboratory) take bytes from the file system, so that every reader parses memory.
#include <cstdint>
#include <string>

namespace penumbra {

/// Largest file read_input_file accepts by default (64 GiB): above it the size is more likely a
/// mistake (a sparse or special file) than a mesh.
inline constexpr std::uint64_t kMaxInputFileBytes = std::uint64_t{64} << 30;

/// What a file of this st_mode is when it is not a regular file, in words ("a directory", "a FIFO
/// (named pipe)", "a character device", ...); "" for a regular file.
std::string file_type_name(unsigned mode);

/// Returns the whole content of the regular file at `path`. Refuses, before reading anything,
/// what is not a regular file (a directory, FIFO, socket or device such as /dev/zero) and files
/// larger than `max_bytes`; reads at most the size the file had when opened. Throws InputError
/// "path: problem".
std::string read_input_file(const std::string& path, std::uint64_t max_bytes = kMaxInputFileBytes);

}  // namespace penumbra
