#pragma once
/// Gzip-compressed input (pbrt's `.pbrt.gz` includes and `.ply.gz` meshes), read through
/// read_input_file and inflated in memory with a bound on the decompressed size.
#include <cstdint>
#include <string>
#include <string_view>

namespace penumbra {

/// The decompressed bytes of the gzip data `compressed` (one or more concatenated members, as
/// gzip writes them), named `name` in messages. Throws InputError "name:byte N: problem" for data
/// that is not gzip, corrupt or truncated, for trailing bytes that are not another member, and
/// when the output would exceed `max_bytes` (a few kilobytes can claim gigabytes: a zip bomb).
std::string gunzip(std::string_view compressed, const std::string& name, uint64_t max_bytes);

/// read_input_file(path) inflated by gunzip, bounded by the memory limit (core/memory_limit.h).
std::string read_gzip_file(const std::string& path);

}  // namespace penumbra
