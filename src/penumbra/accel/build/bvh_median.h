#pragma once
/// Object-median splits of BVH nodes: the references are divided in half by centroid along the
/// axis of greatest centroid extent (the "equal counts" split of Pharr, Jakob & Humphreys 2016,
/// "Physically Based Rendering", 3rd ed., section 4.3.1). Fast and balanced (depth
/// ceil(log2(N / leaf))), but blind to the SAH.
/// Also the fallback of the SAH builds when no split separates the references or the tree is
/// too deep.
#include <cstdint>
#include <span>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/build/bvh_split.h"
#include "penumbra/accel/build/prim_ref.h"

namespace penumbra {

/// Moves the floor(n / 2) references with the smallest centroids along the widest axis of
/// `centroids` (their bounds) to the front of `refs` (ties broken by id, so deterministic; when
/// all centroids coincide, the order is kept) and returns that split; `offset` is the absolute
/// index of refs[0], added to `mid`. O(n).
NodeSplit object_median_split(std::span<PrimRef> refs, uint32_t offset, const Bounds3& centroids);

/// The split strategy of `bvh:median`: halve every node larger than a leaf.
struct MedianSplitter {
  const BvhBuildParams& params;  ///< only max_leaf is read
  PrimRef* refs;                 ///< the builder's references

  /// The split of the node over [b, e): a leaf when it fits, else the object median.
  NodeSplit operator()(uint32_t b, uint32_t e, uint32_t /*cap*/, const Bounds3&,
                       const Bounds3& centroids, int) const {
    if (e - b <= uint32_t(params.max_leaf)) return NodeSplit::make_leaf();
    return object_median_split({refs + b, e - b}, b, centroids);
  }
};

}  // namespace penumbra
