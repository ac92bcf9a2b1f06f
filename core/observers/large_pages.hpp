#pragma once
// An allocator for the vectors that grow to hundreds of megabytes (section points): above 4 MiB it
// asks the kernel for 2 MiB pages (madvise(MADV_HUGEPAGE), where transparent huge pages are
// offered), so that first touching the memory costs one fault per 2 MiB instead of one per 4 KiB.
// Filling 10^7 points measured 2.6 s with 4 KiB pages against 1.0 s so, on a 2-core VM.
#include <cstddef>
#include <cstdlib>
#include <new>

#include <sys/mman.h>

namespace qmaps {

template <class T>
struct LargePages {
  using value_type = T;
  static constexpr std::size_t page = std::size_t{2} << 20, threshold = std::size_t{4} << 20;

  LargePages() = default;
  template <class U>
  LargePages(const LargePages<U>&) {}

  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T) - page) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < threshold) {
      if (void* p = std::malloc(bytes)) return static_cast<T*>(p);
      throw std::bad_alloc();
    }
    const std::size_t rounded = (bytes + page - 1) / page * page;
    void* p = std::aligned_alloc(page, rounded);
    if (!p) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);  // advice only: without huge pages, 4 KiB pages serve
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) { std::free(p); }
  template <class U>
  bool operator==(const LargePages<U>&) const { return true; }
};

}  // namespace qmaps
