#pragma once
/// Parameter lists written after a name on the command line: "kdtree:sah,leaf=8,cost=1.5".
#include <map>
#include <set>
#include <string>
#include <string_view>

namespace penumbra {

/// A name with `key=value` (or bare `flag`) parameters. Each getter marks its key as used, so that
/// `check_all_used` can reject misspelt parameters.
class ParamList {
 public:
  /// Parses "name[:k=v,k2=v2,flag]"; throws Error on malformed text.
  static ParamList parse(std::string_view spec);

  const std::string& name() const { return name_; }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  /// Integer parameter or `fallback`; throws Error when present but not an integer in [lo, hi].
  long long get_int(const std::string& key, long long fallback, long long lo, long long hi) const;
  /// Real parameter or `fallback`; throws Error when present but not a finite number in [lo, hi].
  double get_real(const std::string& key, double fallback, double lo, double hi) const;
  /// String parameter or `fallback`.
  std::string get_string(const std::string& key, const std::string& fallback) const;
  /// True when a bare flag (or key=true/1) is present.
  bool get_flag(const std::string& key) const;
  /// Throws Error naming any parameter no getter asked for.
  void check_all_used() const;
  /// The text form "name:k=v,...", keys sorted; flags given as `true` are written bare.
  std::string to_string() const;

 private:
  std::string name_;
  std::map<std::string, std::string> values_;
  mutable std::set<std::string> used_;
};

}  // namespace penumbra
