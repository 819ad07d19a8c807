#include "penumbra/scene/pbrt_params.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

namespace penumbra {

namespace {

using Kind = PbrtToken::Kind;

/// What a type's values are.
enum class ValueKind { kNumber, kInteger, kString, kBool, kSpectrum };

struct TypeInfo {
  ValueKind kind;
  size_t group;  ///< values come in groups of this many
};

// The parameter types of pbrt-v4, with the older spellings it still reads.
const std::map<std::string, std::string>& aliases() {
  static const std::map<std::string, std::string> a = {
      {"point", "point3"}, {"vector", "vector3"}, {"normal", "normal3"}, {"color", "rgb"}};
  return a;
}

const std::map<std::string, TypeInfo>& types() {
  static const std::map<std::string, TypeInfo> t = {
      {"integer", {ValueKind::kInteger, 1}},  {"float", {ValueKind::kNumber, 1}},
      {"point2", {ValueKind::kNumber, 2}},    {"vector2", {ValueKind::kNumber, 2}},
      {"point3", {ValueKind::kNumber, 3}},    {"vector3", {ValueKind::kNumber, 3}},
      {"normal3", {ValueKind::kNumber, 3}},   {"rgb", {ValueKind::kNumber, 3}},
      {"blackbody", {ValueKind::kNumber, 1}}, {"spectrum", {ValueKind::kSpectrum, 1}},
      {"string", {ValueKind::kString, 1}},    {"texture", {ValueKind::kString, 1}},
      {"bool", {ValueKind::kBool, 1}}};
  return t;
}

std::string type_list() {
  std::string s;
  for (const auto& [name, info] : types()) s += (s.empty() ? "" : ", ") + name;
  return s + " (and point, vector, normal, color)";
}

// Stores one value token of parameter `p`.
void add_value(PbrtParam& p, const TypeInfo& info, const PbrtToken& t) {
  const bool is_string = t.kind == Kind::kString;
  switch (info.kind) {
    case ValueKind::kString:
      if (!is_string)
        t.loc.fail("parameter " + p.declaration() + ": expected a quoted string, got " +
                   t.describe());
      p.strings.push_back(t.text);
      return;
    case ValueKind::kBool: {
      // pbrt-v4 writes booleans bare (true) or quoted ("true").
      if (t.text == "true" || t.text == "false") {
        p.bools.push_back(t.text == "true");
        return;
      }
      t.loc.fail("parameter " + p.declaration() + ": expected true or false, got " + t.describe());
    }
    case ValueKind::kSpectrum:
      if (is_string) {
        p.strings.push_back(t.text);
        return;
      }
      break;
    case ValueKind::kNumber:
    case ValueKind::kInteger:
      if (is_string)
        t.loc.fail("parameter " + p.declaration() + ": expected a number, got " + t.describe());
      break;
  }
  const double v = pbrt_number(t);
  if (info.kind == ValueKind::kInteger && v != std::floor(v))
    t.loc.fail("parameter " + p.declaration() + ": expected an integer, got " + t.text);
  p.numbers.push_back(v);
}

// Checks the count of values and their mix once the list is read.
void check_count(const PbrtParam& p, const TypeInfo& info) {
  if (p.size() == 0) p.loc.fail("parameter " + p.declaration() + " has no values");
  if (!p.numbers.empty() && !p.strings.empty())
    p.loc.fail("parameter " + p.declaration() + " mixes numbers and strings");
  if (p.size() % info.group != 0)
    p.loc.fail("parameter " + p.declaration() + " needs a multiple of " +
               std::to_string(info.group) + " values, got " + std::to_string(p.size()));
  if (p.type == "spectrum") {
    if (!p.strings.empty() && p.strings.size() != 1)
      p.loc.fail("parameter " + p.declaration() + " takes one spectrum name or file, got " +
                 std::to_string(p.strings.size()));
    if (p.numbers.size() > 1 && p.numbers.size() % 2 != 0)
      p.loc.fail("parameter " + p.declaration() +
                 " needs (wavelength, value) pairs, got an odd number of values (" +
                 std::to_string(p.numbers.size()) + ")");
  }
  if (p.type == "blackbody" && p.numbers.size() != 1)
    p.loc.fail("parameter " + p.declaration() + " takes one temperature in kelvin, got " +
               std::to_string(p.numbers.size()) + " values");
}

// Splits "type name" (surrounding and repeated spaces allowed).
bool split_declaration(const std::string& s, std::string& type, std::string& name) {
  std::vector<std::string> words;
  std::string w;
  for (char c : s + " ") {
    if (c == ' ' || c == '\t') {
      if (!w.empty()) words.push_back(w);
      w.clear();
    } else {
      w += c;
    }
  }
  if (words.size() != 2) return false;
  type = words[0], name = words[1];
  return true;
}

}  // namespace

std::string pbrt_format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

bool pbrt_parse_number(const std::string& text, double& value) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  value = std::strtod(begin, &end);
  return end != begin && *end == '\0' && std::isfinite(value) && errno != ERANGE;
}

double pbrt_number(const PbrtToken& t) {
  double v;
  if (t.kind != Kind::kWord || !pbrt_parse_number(t.text, v))
    t.loc.fail("expected a number, got " + t.describe());
  return v;
}

void pbrt_warn(std::vector<std::string>& warnings, const PbrtLoc& loc, const std::string& message) {
  warnings.push_back(loc.str() + ": " + message);
}

PbrtParams PbrtParams::parse(PbrtTokenizer& tok) {
  PbrtParams out;
  while (tok.peek().kind == Kind::kString) {
    const PbrtToken decl = tok.next();
    PbrtParam p;
    p.loc = decl.loc;
    if (!split_declaration(decl.text, p.type, p.name))
      decl.loc.fail("expected a parameter declaration \"type name\", got " + decl.describe());
    if (auto a = aliases().find(p.type); a != aliases().end()) p.type = a->second;
    const auto info = types().find(p.type);
    if (info == types().end())
      decl.loc.fail("unknown parameter type \"" + p.type + "\" in " + decl.describe() +
                    " (valid: " + type_list() + ")");
    for (const PbrtParam& q : out.params_)
      if (q.name == p.name)
        decl.loc.fail("parameter \"" + p.name + "\" given twice (first at " + q.loc.str() + ")");
    const PbrtToken first = tok.next();
    if (first.kind == Kind::kOpen) {
      while (true) {
        const PbrtToken v = tok.next();
        if (v.kind == Kind::kClose) break;
        if (v.kind == Kind::kEnd)
          first.loc.fail("unbalanced '[': no matching ']' before the end of the file");
        if (v.kind == Kind::kOpen) v.loc.fail("unbalanced '[': lists do not nest");
        add_value(p, info->second, v);
      }
    } else if (first.kind == Kind::kWord || first.kind == Kind::kString) {
      add_value(p, info->second, first);  // a bare single value
    } else {
      first.loc.fail("parameter " + p.declaration() + ": expected a value or '[', got " +
                     first.describe());
    }
    check_count(p, info->second);
    out.params_.push_back(std::move(p));
  }
  return out;
}

const PbrtParam* PbrtParams::find(const std::string& name, const std::string& types) const {
  for (const PbrtParam& p : params_) {
    if (p.name != name) continue;
    p.used = true;
    const std::string padded = " " + types + " ";
    if (padded.find(" " + p.type + " ") == std::string::npos)
      p.loc.fail("parameter \"" + name + "\" has type " + p.type + ", expected " + types);
    return &p;
  }
  return nullptr;
}

bool PbrtParams::has(const std::string& name) const {
  for (const PbrtParam& p : params_)
    if (p.name == name) return true;
  return false;
}

namespace {
void require_one(const PbrtParam& p) {
  if (p.size() != 1)
    p.loc.fail("parameter " + p.declaration() + " takes one value, got " +
               std::to_string(p.size()));
}
}  // namespace

double PbrtParams::get_float(const std::string& name, double fallback) const {
  const PbrtParam* p = find(name, "float");
  if (!p) return fallback;
  require_one(*p);
  return p->numbers[0];
}

int PbrtParams::get_int(const std::string& name, int fallback) const {
  const PbrtParam* p = find(name, "integer");
  if (!p) return fallback;
  require_one(*p);
  if (std::fabs(p->numbers[0]) > 2147483647.0)
    p->loc.fail("parameter " + p->declaration() + ": integer out of range");
  return int(p->numbers[0]);
}

bool PbrtParams::get_bool(const std::string& name, bool fallback) const {
  const PbrtParam* p = find(name, "bool");
  if (!p) return fallback;
  require_one(*p);
  return p->bools[0];
}

std::string PbrtParams::get_string(const std::string& name, const std::string& fallback) const {
  const PbrtParam* p = find(name, "string");
  if (!p) return fallback;
  require_one(*p);
  return p->strings[0];
}

std::optional<Vec3> PbrtParams::get_vec3(const std::string& name) const {
  const PbrtParam* p = find(name, "point3 vector3 normal3");
  if (!p) return std::nullopt;
  if (p->numbers.size() != 3)
    p->loc.fail("parameter " + p->declaration() + " takes 3 values, got " +
                std::to_string(p->numbers.size()));
  return Vec3(float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2]));
}

std::vector<double> PbrtParams::get_numbers(const std::string& name,
                                            const std::string& types) const {
  const PbrtParam* p = find(name, types);
  return p ? p->numbers : std::vector<double>{};
}

std::vector<Vec3> PbrtParams::get_vec3s(const std::string& name, const std::string& types) const {
  const std::vector<double> v = get_numbers(name, types);
  std::vector<Vec3> out(v.size() / 3);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = Vec3(float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2]));
  return out;
}

std::vector<Vec2> PbrtParams::get_vec2s(const std::string& name) const {
  const PbrtParam* p = find(name, "point2 vector2 float");
  if (!p) return {};
  if (p->numbers.size() % 2 != 0)
    p->loc.fail("parameter " + p->declaration() + " needs pairs of values, got " +
                std::to_string(p->numbers.size()));
  std::vector<Vec2> out(p->numbers.size() / 2);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = Vec2(float(p->numbers[2 * i]), float(p->numbers[2 * i + 1]));
  return out;
}

void PbrtParams::report_unused(std::vector<std::string>& warnings, const std::string& what) const {
  for (const PbrtParam& p : params_)
    if (!p.used)
      pbrt_warn(warnings, p.loc, "unused parameter " + p.declaration() + " (" + what + ")");
}

}  // namespace penumbra
