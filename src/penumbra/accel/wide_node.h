#pragma once
/// The nodes of the wide BVHs: full ones (float boxes) and compressed 8-wide ones (byte planes).
#include <bit>
#include <cstdint>

namespace penumbra {

/// A node of W children: boxes as six rows (lo.x, hi.x, lo.y, hi.y, lo.z, hi.z) of W floats,
/// so the near plane of axis a is row 2a + (direction negative). Empty slots have empty boxes,
/// which no ray hits.
template <int W>
struct alignas(64) WideNode {
  float box[6][W];    ///< children's boxes, one row per plane
  uint32_t child[W];  ///< inner child: node index; leaf child: first leaf slot
  uint32_t count[W];  ///< leaf child: primitive count; 0 for an inner child or an empty slot
};

/// A compressed node of 8 children (Ylitie, Karras & Laine 2017, "Efficient Incoherent Ray
/// Traversal on GPUs Through Compressed Wide BVHs"): each plane of a child's box is a byte q on a
/// grid local to the node, decoded as origin[a] + q * 2^exponent[a] in float (q * 2^e is exact,
/// so one rounding). The builder rounds every plane outward against that very expression, so a
/// decoded box always contains the child's exact box and no hit is lost; the tree is the same
/// as with WideNode<8>. 128 bytes: the boxes fill the first cache line, the children the second.
struct alignas(64) CompressedNode {
  float origin[3];     ///< grid origin per axis: the lower corner of the node's box
  int8_t exponent[3];  ///< grid step per axis is 2^exponent, in [-126, 127]
  uint8_t valid;       ///< bit i set where slot i holds a child
  uint8_t q[6][8];     ///< quantised planes, rows as WideNode's (lo.x, hi.x, lo.y, ...)
  uint32_t child[8];   ///< as WideNode
  uint32_t count[8];   ///< as WideNode

  /// Grid step of axis a.
  float step(int a) const {
    return std::bit_cast<float>(static_cast<uint32_t>(exponent[a] + 127) << 23);
  }
  /// Decoded value of quantised plane q on axis a, as the traversal computes it.
  float decode(int a, uint8_t v) const { return static_cast<float>(v) * step(a) + origin[a]; }
};
static_assert(sizeof(CompressedNode) == 128);

/// Encodes a full 8-wide node; every decoded child box contains the original one.
CompressedNode compress_node(const WideNode<8>& node);

}  // namespace penumbra
