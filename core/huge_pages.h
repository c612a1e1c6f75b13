// Transparent huge pages for the large dense arrays of meshing at scale (issue 17).
//
// Why: the first write to every 4 KiB page of a fresh allocation is a page fault on the writing
// thread. On the 2-core VM of BENCHMARKS.md a fault cost ~10 µs under load: value-initialising
// the 127 MB adjacency list of the 2.53 M-tet grid took 0.42 s of CPU on the calling thread,
// and faults do not get cheaper on more threads (two threads touching half each took as long).
// With MADV_HUGEPAGE the kernel maps 2 MiB at a time (0.02–0.15 s for the same array).
// Only dense arrays that are written whole right after allocation are advised: a sparsely
// written one would gain resident memory. Advice only: ignored where THP is disabled.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace imm {

/// Advises the kernel to back the 2 MiB-aligned part of [data, data + bytes) with huge pages.
/// Call before the memory is first written.
inline void advise_huge_pages(const void* data, std::size_t bytes) {
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  if (data == nullptr || bytes < 2 * kHuge) return;
  const auto at = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (at + kHuge - 1) & ~(kHuge - 1), end = (at + bytes) & ~(kHuge - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

/// The same for the reserved storage of a vector (after reserve(), before resize()).
template <class Vector>
void advise_huge_pages(const Vector& v) {
  advise_huge_pages(v.data(), v.capacity() * sizeof(typename Vector::value_type));
}

/// v.resize(n) after advising huge pages for its storage: the value-initialisation of a large
/// array is a serial pass of page faults otherwise.
template <class Vector>
void resize_advised(Vector& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v);
  v.resize(n);
}

/// A std::allocator whose construct() without arguments default-initialises: a vector of
/// trivially default-constructible elements then grows by resize() without touching the new
/// storage, which the caller writes (on all threads) before reading it. For large arrays whose
/// value-initialisation would be a serial pass of page faults on the calling thread.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>& /*other*/) noexcept {}  // NOLINT: converting, as std::allocator's
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  friend bool operator==(const DefaultInitAllocator&, const DefaultInitAllocator&) noexcept { return true; }
};

/// An array of n default-initialised (untouched) values, advised: for scratch arrays written
/// whole on all threads before they are read, where value-initialising them would be a serial
/// pass of page faults.
template <class T>
std::unique_ptr<T[]> uninitialized_array(std::size_t n) {
  std::unique_ptr<T[]> a(new T[n]);
  advise_huge_pages(a.get(), n * sizeof(T));
  return a;
}

}  // namespace imm
