#pragma once
/// Split-candidate events of the O(N log N) kd-tree build (Wald, Havran 2006, "On building fast
/// kd-Trees for Ray Tracing, and on doing that in O(N log N)"): each primitive box
/// gives, per axis, a start and an end event, or one planar event when the box is flat in that
/// axis. An event is one 64-bit key whose integer order is the order the sweep needs: axis, then
/// position, then type (end < planar < start), then primitive, so sorting is an integer sort and
/// two lists merge with std::merge.
#include <bit>
#include <cstdint>
#include <vector>

#include "penumbra/accel/build/kd_node.h"

namespace penumbra {

/// Axis (2 bits) | position as an order-preserving integer (32) | type (2) | local primitive (28).
using KdEvent = uint64_t;

/// Event types, in sweep order at equal positions.
enum KdEventType : uint32_t { kKdEnd = 0, kKdPlanar = 1, kKdStart = 2 };

/// Most primitives in one node that events can number.
inline constexpr uint32_t kKdMaxEventPrims = (1u << 28) - 1;

/// Maps a float to an unsigned integer of the same order (-0 and +0 alike).
inline uint32_t kd_float_key(float f) {
  const uint32_t u = std::bit_cast<uint32_t>(f + 0.0f);  // -0 + 0 = +0
  return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

/// The float of an order-preserving key.
inline float kd_key_float(uint32_t k) {
  return std::bit_cast<float>((k & 0x80000000u) ? (k & 0x7fffffffu) : ~k);
}

/// An event of primitive `prim` (local index) at `pos` on `axis`.
inline KdEvent kd_event(int axis, float pos, KdEventType type, uint32_t prim) {
  return (uint64_t(axis) << 62) | (uint64_t(kd_float_key(pos)) << 30) | (uint64_t(type) << 28) |
         prim;
}

/// The plane (axis and position) of an event, as the high 34 bits.
inline uint64_t kd_event_plane(KdEvent e) {
  return e >> 30;
}
/// The plane and type of an event, as the high 36 bits.
inline uint64_t kd_event_plane_type(KdEvent e) {
  return e >> 28;
}
inline int kd_event_axis(KdEvent e) {
  return int(e >> 62);
}
inline float kd_event_pos(KdEvent e) {
  return kd_key_float(uint32_t(e >> 30));
}
inline uint32_t kd_event_prim(KdEvent e) {
  return uint32_t(e) & kKdMaxEventPrims;
}
/// The same event for primitive `prim`.
inline KdEvent kd_event_with_prim(KdEvent e, uint32_t prim) {
  return (e & ~uint64_t(kKdMaxEventPrims)) | prim;
}

/// Appends the events of box `b` of local primitive `prim`: per axis a planar event when the box
/// is flat in it, else a start and an end event.
inline void kd_add_events(std::vector<KdEvent>& out, const Bounds3& b, uint32_t prim) {
  for (int axis = 0; axis < 3; ++axis) {
    if (b.lo[axis] == b.hi[axis]) {
      out.push_back(kd_event(axis, b.lo[axis], kKdPlanar, prim));
    } else {
      out.push_back(kd_event(axis, b.lo[axis], kKdStart, prim));
      out.push_back(kd_event(axis, b.hi[axis], kKdEnd, prim));
    }
  }
}

}  // namespace penumbra
