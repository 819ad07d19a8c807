#pragma once
/// The contract every fuzz target checks: a reader given any bytes either returns or throws
/// penumbra::Error, whose message holds no raw control bytes and no bytes that are not UTF-8.
/// Any other exception, a crash, a sanitizer report, a leak, a hang or a large allocation is a
/// finding (libFuzzer stops and writes the input to crash-*, timeout-* or oom-*).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "penumbra/core/error.h"

namespace penumbra::fuzz {

/// Whether `s` is printable UTF-8 without control characters.
inline bool is_clean_message(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    if (b < 0x20 || b == 0x7f) return false;
    if (b < 0x80) {
      ++i;
      continue;
    }
    const std::size_t n = b >= 0xf0 ? 4 : b >= 0xe0 ? 3 : b >= 0xc2 ? 2 : 0;
    if (n == 0 || i + n > s.size()) return false;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return false;
    if (b == 0xc2 && static_cast<unsigned char>(s[i + 1]) < 0xa0) return false;  // C1 controls
    i += n;
  }
  return true;
}

/// Runs `read` (a callable taking the input as a string_view) under the contract above.
template <class Read>
int check_reader(const std::uint8_t* data, std::size_t size, Read&& read) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    read(bytes);
  } catch (const Error& e) {
    if (!is_clean_message(e.what())) {
      std::fprintf(stderr, "message with raw bytes:\n%s\n", e.what());
      std::abort();
    }
  }
  return 0;
}

}  // namespace penumbra::fuzz
