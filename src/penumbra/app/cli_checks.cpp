#include "penumbra/app/cli_checks.h"

#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

#include <fmt/format.h>

namespace penumbra::app {
namespace {

// Parses all of `s` as a base-10 T; false on anything else, overflow included.
template <class T>
bool parse_whole(const std::string& s, T& value) {
  const char* end = s.data() + s.size();
  const auto [p, ec] = std::from_chars(s.data(), end, value);
  return ec == std::errc() && p == end;
}

// The offending text, cut short: a message never quotes a huge argument whole.
std::string shown_text(const std::string& s) {
  return "'" + (s.size() > 40 ? s.substr(0, 40) + "...'" : s + "'");
}

template <class T>
CLI::Validator range_check(T lo, T hi) {
  const std::string range = fmt::format("[{}, {}]", lo, hi);
  return CLI::Validator(
      [lo, hi, range](std::string& s) -> std::string {
        T v{};
        if (!parse_whole(s, v) || v < lo || v > hi)
          return "expected a decimal integer in " + range + ", got " + shown_text(s);
        s = fmt::format("{}", v);  // CLI11 would read a leading zero as octal: "010" -> 8
        return {};
      },
      range);
}

}  // namespace

CLI::Validator integer_in(int64_t lo, int64_t hi) {
  return range_check(lo, hi);
}

CLI::Validator unsigned_in(uint64_t lo, uint64_t hi) {
  return range_check(lo, hi);
}

CLI::Validator positive_finite() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        double v = 0;
        if (!parse_whole(s, v) || !std::isfinite(v) || !(v > 0))
          return "expected a finite number greater than 0, got " + shown_text(s);
        return {};
      },
      "POSITIVE");
}

}  // namespace penumbra::app
