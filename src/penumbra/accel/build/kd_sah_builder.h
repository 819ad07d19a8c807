#pragma once
/// The surface area heuristic kd-tree build in O(N log N) of Wald, Havran 2006 ("On building fast
/// kd-Trees for Ray Tracing, and on doing that in O(N log N)", IEEE Symposium on Interactive Ray
/// Tracing): events are sorted once for all three axes; each node sweeps its sorted event list
/// once, evaluating every candidate plane with the SAH (MacDonald, Booth 1990, "Heuristics for
/// ray tracing using space subdivision"), including the bonus for cutting off empty space; the
/// chosen plane's primitives are classified below / above / both, straddling ones are clipped to
/// each child ("perfect splits"), and the children's event lists are made by filtering the
/// parent's (which keeps them sorted) and merging in the sorted events of the clipped boxes.
#include <vector>

#include "penumbra/accel/build/kd_node.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// Builds a kd-tree over `refs` (the valid primitives of `prims`, with their boxes) inside
/// `bounds`. Children with more than params.parallel_min references are built in parallel; the
/// tree is the same for every thread count.
KdSubtree build_kd_sah(const PrimitiveSet& prims, std::vector<KdPrim> refs, const Bounds3& bounds,
                       const KdBuildParams& params);

}  // namespace penumbra
