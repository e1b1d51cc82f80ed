// std::vector with storage aligned to a cache line.
//
// The frame planes (depth, ids, S scratch, u16 sums) are read and written in SIMD vectors
// at lane-aligned x on rows padded to 64 pixels (spec §8), but a large std::vector comes
// from malloc at 16 bytes past a page, so every 64-byte AVX-512 access straddled two cache
// lines. Aligning the storage makes those accesses whole lines. Values are unaffected.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace penumbra::raster {

inline constexpr size_t kCacheLine = 64;

template <class T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}
  T* allocate(size_t n) {
    return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{kCacheLine}));
  }
  void deallocate(T* p, size_t) { ::operator delete (p, std::align_val_t{kCacheLine}); }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const {
    return true;
  }
};

template <class T>
using AlignedVector = std::vector<T, CacheLineAllocator<T>>;

}  // namespace penumbra::raster
