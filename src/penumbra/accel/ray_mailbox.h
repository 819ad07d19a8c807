#pragma once
/// Per-ray mailbox for spatial subdivisions (grid, octree), where one primitive is referenced by
/// many cells and a ray would otherwise test it again in every cell it crosses (Amanatides & Woo
/// 1987, "A Fast Voxel Traversal Algorithm for Ray Tracing", section 4). The classic form stores
/// a ray id per primitive, which is not thread-safe without atomics; this one lives on the ray's
/// stack: a small direct-mapped table of the primitive ids tested so far. A collision evicts the
/// older id, so a primitive may occasionally be tested twice, which costs time but not
/// correctness (the test is the same and the hit record keeps the closer hit). Also the loop over
/// a cell's or leaf's references that both structures share.
#include <cstdint>
#include <string_view>
#include <type_traits>

#include <fmt/format.h>

#include "penumbra/accel/traversal_cost.h"
#include "penumbra/core/error.h"
#include "penumbra/core/params.h"
#include "penumbra/geometry/hit.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// Direct-mapped set of recently tested primitive ids; `kSize` is a power of two (0 disables it).
template <int kSize>
class RayMailbox {
  static_assert(kSize == 0 || (kSize & (kSize - 1)) == 0, "mailbox size must be a power of two");

 public:
  RayMailbox() {
    for (auto& s : slots_) s = kNoPrim;
  }
  /// True when `id` was not recorded yet; records it. Consecutive mesh ids are spatial
  /// neighbours, so the low bits spread the ids met along a ray over the slots.
  bool first_visit(uint32_t id) {
    uint32_t& s = slots_[id & (kSize - 1)];
    if (s == id) return false;
    s = id;
    return true;
  }

 private:
  uint32_t slots_[kSize];
};

/// No mailbox: every reference is tested.
template <>
class RayMailbox<0> {
 public:
  /// Always true.
  bool first_visit(uint32_t) { return true; }
};

/// Tests the references [begin, end) of a cell or leaf on (ray.tmin, hit.t), skipping ids the
/// mailbox has seen; updates `hit` and returns true when anything was hit (kAnyHit: at the first
/// hit). kTriangles: the set holds only triangles and `tris` their vertices in reference order
/// (three per reference), so the leaf streams through memory and skips the kind switch. `cost`
/// counts the primitives tested (not those the mailbox skipped).
template <bool kAnyHit, bool kTriangles, int kSize, class Cost = NoCost>
inline bool test_mailboxed(const PrimitiveSet& prims, const uint32_t* ids, const Vec3* tris,
                           uint32_t begin, uint32_t end, const PreparedRay& pr, Hit& hit,
                           RayMailbox<kSize>& mailbox, Cost cost = {}) {
  bool found = false;
  for (uint32_t i = begin; i < end; ++i) {
    const uint32_t id = ids[i];
    if (!mailbox.first_visit(id)) continue;
    cost.prims(1);
    bool h;
    if constexpr (kTriangles) {
      const Vec3* v = tris + 3 * size_t(i);
      float t, u, w;
      h = intersect_triangle(pr, v[0], v[1], v[2], pr.ray.tmin, tie_bound(hit, id), t, u, w);
      if (h) hit = {t, u, w, id};
    } else {
      h = prims.intersect(id, pr, hit);
    }
    if (h) {
      if constexpr (kAnyHit) return true;
      found = true;
    }
  }
  return found;
}

/// Reads mailbox=N (0, 8, 16, 32 or 64; default `fallback`) for `structure`; throws Error on
/// another value.
inline int read_mailbox_size(const ParamList& params, int fallback, std::string_view structure) {
  const auto size = int(params.get_int("mailbox", fallback, 0, 64));
  if (size != 0 && size != 8 && size != 16 && size != 32 && size != 64)
    throw Error(fmt::format("{}: mailbox={} must be 0, 8, 16, 32 or 64", structure, size));
  return size;
}

/// Calls f(triangles, size) with both as compile-time constants (std::bool_constant and
/// std::integral_constant<int, ...>): one traversal instance per mailbox size and leaf layout.
template <class F>
bool dispatch_mailbox(int size, bool triangles, const F& f) {
  const auto with_size = [&](auto size_tag) {
    return triangles ? f(std::true_type{}, size_tag) : f(std::false_type{}, size_tag);
  };
  switch (size) {
    case 0:
      return with_size(std::integral_constant<int, 0>{});
    case 8:
      return with_size(std::integral_constant<int, 8>{});
    case 32:
      return with_size(std::integral_constant<int, 32>{});
    case 64:
      return with_size(std::integral_constant<int, 64>{});
    default:
      return with_size(std::integral_constant<int, 16>{});
  }
}

}  // namespace penumbra
