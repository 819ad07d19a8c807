#include "penumbra/core/params.h"

#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/core/error.h"

namespace penumbra {

ParamList ParamList::parse(std::string_view spec) {
  ParamList p;
  const size_t colon = spec.find(':');
  p.name_ = std::string(spec.substr(0, colon));
  if (p.name_.empty()) throw Error(fmt::format("'{}': missing name before ':'", spec));
  if (colon == std::string_view::npos) return p;
  std::string_view rest = spec.substr(colon + 1);
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    if (item.empty()) throw Error(fmt::format("'{}': empty parameter", spec));
    const size_t eq = item.find('=');
    const std::string key(item.substr(0, eq));
    const std::string value = eq == std::string_view::npos ? "true" : std::string(item.substr(eq + 1));
    if (key.empty() || value.empty())
      throw Error(fmt::format("'{}': malformed parameter '{}'", spec, item));
    if (!p.values_.emplace(key, value).second)
      throw Error(fmt::format("'{}': parameter '{}' given twice", spec, key));
  }
  return p;
}

long long ParamList::get_int(const std::string& key, long long fallback, long long lo,
                             long long hi) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  used_.insert(key);
  long long v = 0;
  const auto& s = it->second;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size())
    throw Error(fmt::format("{}: parameter '{}' must be an integer, got '{}'", name_, key, s));
  if (v < lo || v > hi)
    throw Error(fmt::format("{}: parameter '{}' = {} is outside [{}, {}]", name_, key, v, lo, hi));
  return v;
}

double ParamList::get_real(const std::string& key, double fallback, double lo, double hi) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  used_.insert(key);
  double v = 0;
  const auto& s = it->second;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v))
    throw Error(fmt::format("{}: parameter '{}' must be a number, got '{}'", name_, key, s));
  if (v < lo || v > hi)
    throw Error(fmt::format("{}: parameter '{}' = {} is outside [{}, {}]", name_, key, v, lo, hi));
  return v;
}

std::string ParamList::get_string(const std::string& key, const std::string& fallback) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  used_.insert(key);
  return it->second;
}

bool ParamList::get_flag(const std::string& key) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return false;
  used_.insert(key);
  if (it->second == "true" || it->second == "1") return true;
  if (it->second == "false" || it->second == "0") return false;
  throw Error(fmt::format("{}: flag '{}' must be true or false, got '{}'", name_, key, it->second));
}

void ParamList::check_all_used() const {
  for (const auto& [key, value] : values_)
    if (!used_.count(key)) throw Error(fmt::format("{}: unknown parameter '{}'", name_, key));
}

std::string ParamList::to_string() const {
  std::string s = name_;
  char sep = ':';
  for (const auto& [key, value] : values_) {
    // A bare flag stays bare ("kdtree:sah", not "kdtree:sah=true"); parse() reads it back.
    s += value == "true" ? fmt::format("{}{}", sep, key) : fmt::format("{}{}={}", sep, key, value);
    sep = ',';
  }
  return s;
}

}  // namespace penumbra
