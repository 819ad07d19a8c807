#pragma once
/// An allocator for large flat arrays (acceleration structures, primitive sets): cache-line
/// aligned, and on Linux backed by transparent huge pages when large.
#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace penumbra {

/// Cache-line-aligned allocator; allocations of 2 MiB or more are aligned to 2 MiB and advised
/// as huge pages (madvise MADV_HUGEPAGE). Random traversal of node and triangle arrays of tens of
/// megabytes otherwise misses the TLB on most node visits; 2 MiB pages cover 512 times more
/// memory per TLB entry.
template <class T>
struct ArrayAllocator {
  using value_type = T;
  static constexpr size_t kLine = 64;
  static constexpr size_t kHuge = size_t(2) << 20;

  ArrayAllocator() = default;
  template <class U>
  ArrayAllocator(const ArrayAllocator<U>&) {}

  T* allocate(size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < kHuge) return static_cast<T*>(::operator new(bytes, std::align_val_t(kLine)));
    const size_t rounded = (bytes + kHuge - 1) / kHuge * kHuge;
    void* p = ::operator new(rounded, std::align_val_t(kHuge));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure leaves ordinary pages
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) {
    const size_t bytes = n * sizeof(T);
    ::operator delete(p, std::align_val_t(bytes < kHuge ? kLine : kHuge));
  }
  template <class U>
  bool operator==(const ArrayAllocator<U>&) const {
    return true;
  }
};

/// ArrayAllocator whose value-initialising construction (`vector(n)`, `resize(n)`) leaves the
/// elements unwritten, for scratch arrays that the code fills before it reads them: a page is
/// then first touched by the write that fills it, not by a zeroing pass before it (on a million
/// triangles the BVH build's references and scratch nodes are about 100 MB). Only for types whose
/// objects the allocation itself creates (trivially copyable and destructible aggregates such as
/// PrimRef and BvhNode: implicit-lifetime types, C++20 [intro.object]).
template <class T>
struct NoInitArrayAllocator : ArrayAllocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = NoInitArrayAllocator<U>;
  };

  NoInitArrayAllocator() = default;
  template <class U>
  NoInitArrayAllocator(const NoInitArrayAllocator<U>&) {}

  /// Default construction: nothing written.
  template <class U>
  void construct(U*) noexcept {
    static_assert(std::is_trivially_copyable_v<U> && std::is_trivially_destructible_v<U>);
  }
  /// Any other construction as usual.
  template <class U, class A, class... Rest>
  void construct(U* p, A&& a, Rest&&... rest) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a), std::forward<Rest>(rest)...);
  }
  template <class U>
  bool operator==(const NoInitArrayAllocator<U>&) const {
    return true;
  }
};

}  // namespace penumbra
