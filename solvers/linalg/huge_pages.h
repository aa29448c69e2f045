// Large work buffers on transparent huge pages (Linux, where THP is "madvise": Debian's
// default). Internal to the library. Block solves touch rows scattered over buffers of hundreds
// of MB, which 2 MB pages keep within the TLB's reach (docs/decisions.md D-063).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ifem::solvers {

/// Asks the kernel to back [p, p + bytes) with huge pages where whole 2 MB pages fit inside it.
/// Call before the memory is first touched (pages already faulted in stay small). A hint: a
/// no-op where unsupported.
inline void advise_huge_pages(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::size_t kHuge = std::size_t(2) << 20;
  const auto begin = (reinterpret_cast<std::size_t>(p) + kHuge - 1) / kHuge * kHuge;
  const auto end = (reinterpret_cast<std::size_t>(p) + bytes) / kHuge * kHuge;
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

/// std::allocator, except that blocks of at least 4 MB are 2 MB-aligned and advised onto huge
/// pages before first use.
template <class T>
struct HugePageAllocator {
  typedef T value_type;  // the name std::allocator_traits requires (not our CamelCase)
  static constexpr std::size_t kHuge = std::size_t(2) << 20;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < 2 * kHuge) return std::allocator<T>().allocate(n);
    const std::size_t rounded = (bytes + kHuge - 1) / kHuge * kHuge;
    void* p = std::aligned_alloc(kHuge, rounded);
    if (!p) throw std::bad_alloc();
    advise_huge_pages(p, rounded);
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < 2 * kHuge) {
      std::allocator<T>().deallocate(p, n);
    } else {
      std::free(p);
    }
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const HugePageAllocator<U>&) const noexcept {
    return false;
  }
};

/// A vector of doubles on huge pages when large.
using HugeVector = std::vector<double, HugePageAllocator<double>>;

}  // namespace ifem::solvers
