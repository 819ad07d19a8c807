#pragma once
/// The bound on what one allocation sized by the user's input may take (a film's pixels, a photon
/// map, a form-factor matrix): estimated before allocating and refused with a message that names
/// the parameter, instead of a bare std::bad_alloc or the system's out-of-memory killer.
#include <cstdint>
#include <string>
#include <string_view>

namespace penumbra {

/// This machine's memory in bytes: the physical memory, or the control group's limit (cgroup v2
/// memory.max, v1 memory.limit_in_bytes) when that is smaller, as in a container.
uint64_t machine_memory();

/// The limit in bytes: set_memory_limit's, else three quarters of machine_memory().
uint64_t memory_limit();
/// Sets the limit (the CLI's --max-memory); 0 restores the default. Process-wide, like the
/// thread count: set it before building or rendering, not while they run.
void set_memory_limit(uint64_t bytes);

/// Sets the limit for its lifetime (0 leaves it as it is) and restores the previous setting.
class ScopedMemoryLimit {
 public:
  explicit ScopedMemoryLimit(uint64_t bytes);
  ~ScopedMemoryLimit();
  ScopedMemoryLimit(const ScopedMemoryLimit&) = delete;
  ScopedMemoryLimit& operator=(const ScopedMemoryLimit&) = delete;

 private:
  uint64_t previous_;
};

/// Throws Error "WHAT needs SIZE, more than the memory limit of LIMIT (...); HINT" when `bytes`
/// exceeds memory_limit(). `what` names the parameter ("--resolution 65536x65536: the film of
/// 4294967296 pixels"), `hint` says what to change ("" for none).
void check_memory(double bytes, std::string_view what, std::string_view hint = "");

/// Bytes in binary units for messages: "512 B", "3.0 KiB", "17.4 GiB".
std::string format_bytes(double bytes);

/// Parses a size for --max-memory: a number with an optional unit K, M, G, T (powers of 1024;
/// "KiB", "KB", "k" are the same) or B; "16G", "1.5GiB", "800M", "1073741824". Throws Error
/// naming the text for anything else, zero, or more than 2^60 bytes.
uint64_t parse_memory_size(std::string_view text);

}  // namespace penumbra
