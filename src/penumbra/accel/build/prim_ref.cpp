#include "penumbra/accel/build/prim_ref.h"

#include <algorithm>

#include "penumbra/core/parallel.h"

namespace penumbra {

namespace {
/// Primitives per parallel chunk: fixed, so the chunking does not depend on the thread count.
constexpr size_t kChunk = 16384;
}  // namespace

PrimRefs make_prim_refs(const PrimitiveSet& prims) {
  const size_t n = prims.size();
  const size_t chunks = (n + kChunk - 1) / kChunk;
  PrimRefs out;
  out.refs.resize(n);
  std::vector<Bounds3> chunk_bounds(chunks), chunk_centroids(chunks);
  std::vector<size_t> chunk_valid(chunks, 0);
  // Boxes per chunk, written at the primitive's own index; invalid ones are marked by id.
  parallel_for(chunks, [&](size_t c) {
    const size_t begin = c * kChunk, end = std::min(n, begin + kChunk);
    Bounds3 b, cb;
    size_t valid = 0;
    for (size_t i = begin; i < end; ++i) {
      const Bounds3 box = prims.prim_bounds(static_cast<uint32_t>(i));
      PrimRef& r = out.refs[i];
      if (box.empty()) {
        r = {Vec3(0.0f), kNoPrim, Vec3(0.0f), 0};
        continue;
      }
      // x + 0 turns -0 into +0 and leaves every other value unchanged.
      r = {box.lo + Vec3(0.0f), static_cast<uint32_t>(i), box.hi + Vec3(0.0f), 0};
      b.extend(r.bounds());
      cb.extend(r.centroid2());
      ++valid;
    }
    chunk_bounds[c] = b, chunk_centroids[c] = cb, chunk_valid[c] = valid;
  });
  size_t valid = 0;
  for (size_t c = 0; c < chunks; ++c) {
    out.bounds.extend(chunk_bounds[c]);
    out.centroid_bounds.extend(chunk_centroids[c]);
    valid += chunk_valid[c];
  }
  // Drop the invalid references, keeping id order (rare: only non-finite primitives).
  if (valid != n)
    out.refs.erase(std::remove_if(out.refs.begin(), out.refs.end(),
                                  [](const PrimRef& r) { return r.id == kNoPrim; }),
                   out.refs.end());
  return out;
}

}  // namespace penumbra
