#include "penumbra/accel/build/prim_ref.h"

#include <algorithm>

#include "penumbra/core/parallel.h"
#include "penumbra/geometry/triangle.h"

#if defined(__SSE4_1__)
#include <smmintrin.h>
#endif

namespace penumbra {

namespace {
/// Primitives per parallel chunk: fixed, so the chunking does not depend on the thread count.
constexpr size_t kChunk = 16384;

/// Totals of one chunk of references.
struct ChunkTotals {
  Bounds3 bounds, centroids;
  size_t valid = 0;
};

/// The references of primitives [begin, end), written at their own index (invalid ones marked
/// by id), by the primitive's own box (PrimitiveSet::prim_bounds).
ChunkTotals generic_refs(const PrimitiveSet& prims, size_t begin, size_t end, PrimRef* out) {
  ChunkTotals t;
  for (size_t i = begin; i < end; ++i) {
    const Bounds3 box = prims.prim_bounds(static_cast<uint32_t>(i));
    PrimRef& r = out[i];
    if (box.empty() || never_hit(prims, static_cast<uint32_t>(i))) {
      r = {Vec3(0.0f), kNoPrim, Vec3(0.0f), 0};
      continue;
    }
    r = make_prim_ref(box, static_cast<uint32_t>(i));
    t.bounds.extend(r.bounds());
    t.centroids.extend(r.centroid2());
    ++t.valid;
  }
  return t;
}

#if defined(__SSE4_1__)
/// generic_refs for a set of static triangles, four lanes at a time: the same boxes (a triangle
/// is valid when its nine coordinates are at most kMaxCoordinate in magnitude, which also
/// rejects NaN and infinities, as prim_bounds does, and repeated_vertex is false) and the same
/// totals.
ChunkTotals triangle_refs(const PrimitiveSet& prims, size_t begin, size_t end, PrimRef* out) {
  const __m128 limit = _mm_set1_ps(kMaxCoordinate);
  const __m128 sign = _mm_set1_ps(-0.0f);
  const __m128 zero = _mm_setzero_ps();
  const __m128 inf = _mm_set1_ps(kInfinity);
  __m128 blo = inf, bhi = _mm_sub_ps(zero, inf), clo = inf, chi = _mm_sub_ps(zero, inf);
  ChunkTotals t;
  for (size_t i = begin; i < end; ++i) {
    const Vec3* tri = prims.triangle(static_cast<uint32_t>(i));
    const float* v = &tri[0].x;
    // Vertices 0 and 1 from 16-byte loads inside the triangle's 36 bytes; vertex 2 from the
    // load ending at its last coordinate, rotated (lane 3 is never used).
    const __m128 a = _mm_loadu_ps(v), b = _mm_loadu_ps(v + 3);
    const __m128 tail = _mm_loadu_ps(v + 5);
    const __m128 c = _mm_shuffle_ps(tail, tail, _MM_SHUFFLE(0, 3, 2, 1));
    const __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmple_ps(_mm_andnot_ps(sign, a), limit),
                                            _mm_cmple_ps(_mm_andnot_ps(sign, b), limit)),
                                 _mm_cmple_ps(_mm_andnot_ps(sign, c), limit));
    PrimRef& r = out[i];
    if ((_mm_movemask_ps(ok) & 7) != 7 || repeated_vertex(tri[0], tri[1], tri[2])) {
      r = {Vec3(0.0f), kNoPrim, Vec3(0.0f), 0};
      continue;
    }
    // x + 0 turns -0 into +0 and leaves every other value unchanged.
    const __m128 lo = _mm_add_ps(_mm_min_ps(_mm_min_ps(a, b), c), zero);
    const __m128 hi = _mm_add_ps(_mm_max_ps(_mm_max_ps(a, b), c), zero);
    const __m128i id = _mm_cvtsi32_si128(static_cast<int>(static_cast<uint32_t>(i)));
    _mm_store_ps(&r.lo.x, _mm_blend_ps(lo, _mm_castsi128_ps(_mm_slli_si128(id, 12)), 8));
    _mm_store_ps(&r.hi.x, _mm_blend_ps(hi, zero, 8));
    blo = _mm_min_ps(blo, lo), bhi = _mm_max_ps(bhi, hi);
    const __m128 c2 = _mm_add_ps(lo, hi);
    clo = _mm_min_ps(clo, c2), chi = _mm_max_ps(chi, c2);
    ++t.valid;
  }
  if (t.valid) {
    alignas(16) float l[4], h[4], cl[4], ch[4];
    _mm_store_ps(l, blo), _mm_store_ps(h, bhi), _mm_store_ps(cl, clo), _mm_store_ps(ch, chi);
    t.bounds = Bounds3({l[0], l[1], l[2]}, {h[0], h[1], h[2]});
    t.centroids = Bounds3({cl[0], cl[1], cl[2]}, {ch[0], ch[1], ch[2]});
  }
  return t;
}
#endif
}  // namespace

bool never_hit(const PrimitiveSet& prims, uint32_t id) {
  if (prims.kind(id) != PrimKind::kTriangle || prims.moving(id)) return false;
  const Vec3* v = prims.triangle(id);
  return repeated_vertex(v[0], v[1], v[2]);
}

PrimRefs make_prim_refs(const PrimitiveSet& prims, size_t spare) {
  const size_t n = prims.size();
  const size_t chunks = (n + kChunk - 1) / kChunk;
  PrimRefs out;
  out.refs.reserve(n + spare);
  out.refs.resize(n);
  std::vector<ChunkTotals> totals(chunks);
  // Boxes per chunk, written at the primitive's own index; invalid ones are marked by id.
  [[maybe_unused]] const bool triangles = prims.all_triangles();  // used with SSE4.1
  parallel_for(chunks, [&](size_t c) {
    const size_t begin = c * kChunk, end = std::min(n, begin + kChunk);
#if defined(__SSE4_1__)
    if (triangles) {
      totals[c] = triangle_refs(prims, begin, end, out.refs.data());
      return;
    }
#endif
    totals[c] = generic_refs(prims, begin, end, out.refs.data());
  });
  size_t valid = 0;
  for (const ChunkTotals& t : totals) {
    out.bounds.extend(t.bounds);
    out.centroid_bounds.extend(t.centroids);
    valid += t.valid;
  }
  // Drop the invalid references, keeping id order (non-finite primitives, and triangles that no
  // ray can hit).
  if (valid != n)
    out.refs.erase(std::remove_if(out.refs.begin(), out.refs.end(),
                                  [](const PrimRef& r) { return r.id == kNoPrim; }),
                   out.refs.end());
  return out;
}

}  // namespace penumbra
