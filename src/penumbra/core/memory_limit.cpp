#include "penumbra/core/memory_limit.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "penumbra/core/error.h"

namespace penumbra {
namespace {

std::atomic<uint64_t> g_limit{0};  // 0: the default

// The first number in a control-group file; 0 when it is missing, unreadable or "max".
uint64_t read_cgroup_limit(const char* path) {
  std::ifstream f(path);
  uint64_t v = 0;
  if (f >> v) return v;
  return 0;
}

}  // namespace

uint64_t machine_memory() {
  static const uint64_t bytes = [] {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    uint64_t m = pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : uint64_t(8) << 30;
    for (const char* p :
         {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
      const uint64_t c = read_cgroup_limit(p);
      if (c > 0) m = std::min(m, c);  // v1 reports "no limit" as a huge number: min keeps m
    }
    return m;
  }();
  return bytes;
}

uint64_t memory_limit() {
  const uint64_t set = g_limit.load(std::memory_order_relaxed);
  return set ? set : machine_memory() / 4 * 3;
}

void set_memory_limit(uint64_t bytes) {
  g_limit.store(bytes, std::memory_order_relaxed);
}

ScopedMemoryLimit::ScopedMemoryLimit(uint64_t bytes) : previous_(g_limit.load()) {
  if (bytes) set_memory_limit(bytes);
}

ScopedMemoryLimit::~ScopedMemoryLimit() {
  set_memory_limit(previous_);
}

std::string format_bytes(double bytes) {
  static constexpr const char* kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 6) bytes /= 1024.0, ++u;
  return u == 0 ? fmt::format("{:.0f} B", bytes) : fmt::format("{:.1f} {}", bytes, kUnits[u]);
}

void check_memory(double bytes, std::string_view what, std::string_view hint) {
  const uint64_t limit = memory_limit();
  if (bytes <= double(limit)) return;  // NaN (an estimate gone wrong) is refused too
  const std::string source =
      g_limit.load(std::memory_order_relaxed)
          ? "set by --max-memory"
          : fmt::format("three quarters of this machine's {}; --max-memory changes it",
                        format_bytes(double(machine_memory())));
  throw Error(fmt::format("{} needs {}, more than the memory limit of {} ({}){}{}", what,
                          format_bytes(bytes), format_bytes(double(limit)), source,
                          hint.empty() ? "" : "; ", hint));
}

uint64_t parse_memory_size(std::string_view text) {
  const auto bad = [&]() -> Error {
    return Error(fmt::format("'{}' is not a memory size (examples: 16G, 800M, 1.5GiB)", text));
  };
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr == text.data() || !(value > 0) || !std::isfinite(value)) throw bad();
  std::string unit(ptr, end);
  std::transform(unit.begin(), unit.end(), unit.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  double scale = 0;
  if (unit.empty() || unit == "b") scale = 1;
  for (int i = 0; i < 4 && scale == 0; ++i) {
    const char* letters = "kmgt";
    const std::string u(1, letters[i]);
    if (unit == u || unit == u + "b" || unit == u + "ib") scale = std::ldexp(1.0, 10 * (i + 1));
  }
  if (scale == 0) throw bad();
  const double bytes = std::floor(value * scale);
  if (!(bytes >= 1) || bytes > std::ldexp(1.0, 60)) throw bad();
  return uint64_t(bytes);
}

}  // namespace penumbra
