#include "penumbra/scene/json_value.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <set>

#include "penumbra/core/error.h"
#include "penumbra/core/text_escape.h"

namespace penumbra {

using nlohmann::json;

namespace {

// Doubles of integral value up to 2^53 are exact, so they may stand for integers.
constexpr double kMaxExactInteger = 9007199254740992.0;

// 1-based line and byte column of `offset` in `text`, as "LINE:COLUMN".
std::string line_column(const std::string& text, size_t offset) {
  offset = std::min(offset, text.size());
  const size_t line =
      1 + static_cast<size_t>(std::count(text.begin(), text.begin() + offset, '\n'));
  const size_t newline = offset == 0 ? std::string::npos : text.rfind('\n', offset - 1);
  const size_t line_start = newline == std::string::npos ? 0 : newline + 1;
  const size_t column = offset - line_start + 1;
  return std::to_string(line) + ":" + std::to_string(column);
}

// The problem part of a nlohmann message: "[json.exception.X] parse error at line 1, column 2:
// PROBLEM" becomes "PROBLEM".
std::string strip_nlohmann_prefix(const std::string& what) {
  size_t start = what.find("] ");
  start = start == std::string::npos ? 0 : start + 2;
  const size_t colon = what.find(": ", what.find("parse error", start));
  if (what.compare(start, 11, "parse error") == 0 && colon != std::string::npos) start = colon + 2;
  return what.substr(start);
}

}  // namespace

JsonPlace JsonPlace::key(std::string_view k) const {
  return {file, path + "/" + json_pointer_escape(k)};
}

JsonPlace JsonPlace::index(size_t i) const {
  return {file, path + "/" + std::to_string(i)};
}

void JsonPlace::fail(const std::string& problem) const {
  throw InputError(file, path, problem);
}

std::string json_pointer_escape(std::string_view key) {
  std::string out;
  out.reserve(key.size());
  for (const char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

json parse_json(const std::string& text, const std::string& file) {
  // UTF-16 and UTF-32 files get a message of their own rather than a syntax error at 1:1.
  if (const auto why = describe_non_text(std::string_view(text).substr(0, 4));
      why && why->starts_with("UTF")) {
    throw InputError(file, "", *why);
  }
  // The containers open at the current parse position, to name the path of a duplicate key.
  struct Frame {
    bool is_object;
    std::string key;   // the member being parsed (objects)
    size_t index = 0;  // the element being parsed (arrays)
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  const auto path = [&stack] {
    std::string p;
    for (const Frame& f : stack)
      p += "/" + (f.is_object ? json_pointer_escape(f.key) : std::to_string(f.index));
    return p;
  };
  const auto element_done = [&stack] {
    if (!stack.empty() && !stack.back().is_object) ++stack.back().index;
  };
  const json::parser_callback_t on_event = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        stack.push_back({true, {}, 0, {}});
        break;
      case json::parse_event_t::array_start:
        stack.push_back({false, {}, 0, {}});
        break;
      case json::parse_event_t::key:
        stack.back().key = parsed.get<std::string>();
        if (!stack.back().keys.insert(stack.back().key).second)
          throw InputError(file, path(), "duplicate key");
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        stack.pop_back();
        element_done();
        break;
      case json::parse_event_t::value:
        element_done();
        break;
    }
    return true;
  };

  try {
    return json::parse(text, on_event, /*allow_exceptions=*/true, /*ignore_comments=*/false);
  } catch (const json::parse_error& e) {
    // e.byte counts the characters read, the offending one included.
    throw InputError(file, line_column(text, e.byte == 0 ? 0 : e.byte - 1),
                     strip_nlohmann_prefix(e.what()));
  } catch (const json::out_of_range& e) {
    // A number too large for a double ("number overflow parsing '1e999'") carries no position:
    // find the quoted token in the text.
    const std::string what = e.what();
    const size_t open = what.find('\''), close = what.rfind('\'');
    std::string place;
    if (open != std::string::npos && close > open + 1) {
      const size_t at = text.find(what.substr(open + 1, close - open - 1));
      if (at != std::string::npos) place = line_column(text, at);
    }
    throw InputError(file, place, strip_nlohmann_prefix(what) + " (not a finite number)");
  }
}

void json_check_keys(const json& object, const JsonPlace& place,
                     const std::vector<std::string>& known, const std::string& context) {
  for (const auto& [name, value] : object.items()) {
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::vector<std::string> sorted = known;
    std::sort(sorted.begin(), sorted.end());
    std::string list;
    for (const std::string& k : sorted) list += (list.empty() ? "" : ", ") + k;
    place.key(name).fail("unknown key (" + context + " takes: " + list + ")");
  }
}

const json* json_find(const json& object, const std::string& key) {
  if (!object.is_object()) return nullptr;
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

const json& json_require(const json& object, const JsonPlace& place, const std::string& key) {
  const json* v = json_find(object, key);
  if (!v) place.fail("missing required key \"" + key + "\"");
  return *v;
}

double json_number(const json& v, const JsonPlace& place) {
  if (!v.is_number()) place.fail("expected a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) place.fail("expected a finite number");
  return d;
}

float json_float(const json& v, const JsonPlace& place) {
  const double d = json_number(v, place);
  if (std::fabs(d) > double(FLT_MAX)) place.fail("number out of single-precision range");
  return static_cast<float>(d);
}

int64_t json_int(const json& v, const JsonPlace& place, int64_t lo, int64_t hi) {
  // Built only on failure: this runs once per mesh index.
  const auto fail = [&](const std::string& got) {
    std::string problem = "expected an integer in [";
    problem.append(std::to_string(lo)).append(", ").append(std::to_string(hi)).append("]");
    place.fail(problem.append(got));
  };
  int64_t i = 0;
  if (v.is_number_unsigned()) {
    const uint64_t u = v.get<uint64_t>();
    if (hi < 0 || u > static_cast<uint64_t>(hi)) fail(", got " + std::to_string(u));
    i = static_cast<int64_t>(u);
  } else if (v.is_number_integer()) {
    i = v.get<int64_t>();
  } else if (v.is_number_float()) {
    const double d = v.get<double>();
    if (!(std::fabs(d) <= kMaxExactInteger) || d != std::floor(d)) fail("");
    i = static_cast<int64_t>(d);
  } else {
    fail("");
  }
  if (i < lo || i > hi) fail(", got " + std::to_string(i));
  return i;
}

uint64_t json_uint64(const json& v, const JsonPlace& place) {
  if (v.is_number_unsigned()) return v.get<uint64_t>();
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (d >= 0 && d <= kMaxExactInteger && d == std::floor(d)) return static_cast<uint64_t>(d);
  }
  place.fail("expected an integer in [0, 18446744073709551615]");
}

bool json_bool(const json& v, const JsonPlace& place) {
  if (!v.is_boolean()) place.fail("expected true or false");
  return v.get<bool>();
}

std::string json_string(const json& v, const JsonPlace& place) {
  if (!v.is_string()) place.fail("expected a string");
  return v.get<std::string>();
}

Vec2 json_vec2(const json& v, const JsonPlace& place) {
  if (!v.is_array() || v.size() != 2) place.fail("expected an array of 2 numbers");
  return {json_float(v[0], place.index(0)), json_float(v[1], place.index(1))};
}

Vec3 json_vec3(const json& v, const JsonPlace& place) {
  if (!v.is_array() || v.size() != 3) place.fail("expected an array of 3 numbers");
  return {json_float(v[0], place.index(0)), json_float(v[1], place.index(1)),
          json_float(v[2], place.index(2))};
}

Rgb json_rgb(const json& v, const JsonPlace& place) {
  if (v.is_number()) return Rgb(json_float(v, place));
  if (!v.is_array() || v.size() != 3) place.fail("expected a number or an array of 3 numbers");
  const Vec3 c = json_vec3(v, place);
  return {c.x, c.y, c.z};
}

Rgb json_radiance(const json& v, const JsonPlace& place) {
  const Rgb c = json_rgb(v, place);
  if (c.r < 0 || c.g < 0 || c.b < 0) place.fail("must not be negative");
  return c;
}

const json& json_array(const json& v, const JsonPlace& place) {
  if (!v.is_array()) place.fail("expected an array");
  return v;
}

}  // namespace penumbra
