#include "penumbra/accel/registry.h"

#include <functional>

#include <fmt/format.h>

#include "penumbra/accel/brute_force.h"
#include "penumbra/accel/bvh.h"
#include "penumbra/core/error.h"

namespace penumbra {

namespace {

struct Entry {
  AccelInfo info;
  std::function<std::unique_ptr<Accelerator>(const ParamList&)> make;
};

template <class T>
std::unique_ptr<Accelerator> create(const ParamList& p) {
  return std::make_unique<T>(p);
}

/// Every structure, written out explicitly: a new one is one line here.
const std::vector<Entry>& entries() {
  static const std::vector<Entry> all = {
      {{"brute", "brute force: every primitive for every ray (the reference)"}, create<BruteForce>},
      {{"bvh", "binary BVH, binned SAH build (leaf=8, bins=16, trav=1)"}, create<Bvh>},
  };
  return all;
}

}  // namespace

const std::vector<AccelInfo>& accelerator_list() {
  static const std::vector<AccelInfo> list = [] {
    std::vector<AccelInfo> l;
    for (const auto& e : entries()) l.push_back(e.info);
    return l;
  }();
  return list;
}

std::unique_ptr<Accelerator> make_accelerator(std::string_view spec) {
  const ParamList params = ParamList::parse(spec);
  for (const auto& e : entries())
    if (e.info.name == params.name()) return e.make(params);
  std::string names;
  for (const auto& e : entries()) names += (names.empty() ? "" : ", ") + e.info.name;
  throw Error(fmt::format("unknown acceleration structure '{}' (valid: {})", params.name(), names));
}

}  // namespace penumbra
