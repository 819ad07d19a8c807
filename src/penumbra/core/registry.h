#pragma once
/// A family's registry of named factories (accelerators, integrators, samplers, materials, ...):
/// entries written out explicitly in one file per family, found by name; an unknown name is an
/// error that lists the valid names.
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/core/error.h"

namespace penumbra {

/// An ordered list of {name, description, factory}; `Factory` is any callable (or value) type.
template <class Factory>
class Registry {
 public:
  /// One registered name.
  struct Entry {
    std::string name;
    std::string description;
    Factory factory;
  };

  /// The entries in registration order (the order `names()` and the error messages list them).
  Registry(std::initializer_list<Entry> entries) : entries_(entries) {}

  /// All entries, in registration order.
  const std::vector<Entry>& entries() const { return entries_; }

  /// All names, in registration order.
  std::vector<std::string> names() const {
    std::vector<std::string> names;
    names.reserve(entries_.size());
    for (const Entry& e : entries_) names.push_back(e.name);
    return names;
  }

  /// The factory registered as `name`, or nullptr when there is none.
  const Factory* find(std::string_view name) const {
    for (const Entry& e : entries_)
      if (e.name == name) return &e.factory;
    return nullptr;
  }

  /// The names joined by ", ": "a, b, c".
  std::string valid_names() const {
    return valid_names([](const std::string&) { return true; });
  }

  /// The names for which `keep(name)` is true, joined by ", " (e.g. to leave out listed variants).
  template <class Keep>
  std::string valid_names(Keep keep) const {
    std::string valid;
    for (const Entry& e : entries_) {
      if (!keep(e.name)) continue;
      if (!valid.empty()) valid += ", ";
      valid += e.name;
    }
    return valid;
  }

  /// "unknown KIND 'NAME' (valid: a, b, c)", for callers that raise their own error type.
  std::string unknown_name_message(std::string_view kind, std::string_view name) const {
    std::string message = "unknown ";
    message.append(kind).append(" '").append(name).append("' (valid: ");
    return message + valid_names() + ")";
  }

  /// The factory registered as `name`; throws Error with `unknown_name_message` when there is none.
  const Factory& get(std::string_view name, std::string_view kind) const {
    if (const Factory* factory = find(name)) return *factory;
    throw Error(unknown_name_message(kind, name));
  }

 private:
  std::vector<Entry> entries_;
};

}  // namespace penumbra
