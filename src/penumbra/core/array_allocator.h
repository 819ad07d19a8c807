#pragma once
/// An allocator for large flat arrays (acceleration structures, primitive sets): cache-line
/// aligned, and on Linux backed by transparent huge pages when large.
#include <cstddef>
#include <new>

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

}  // namespace penumbra
