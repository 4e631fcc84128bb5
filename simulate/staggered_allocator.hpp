#pragma once
// An allocator that starts each large array at its own offset within a memory page.
//
// Why: glibc hands out every large block by mmap, 16 bytes past a page boundary, so element i of
// every per-sphere array falls into the same L1 cache set (the set index is the address modulo
// 4096 on an 8-way, 32 KiB L1). The integrator streams about twenty such arrays at once, more
// than a set has ways, and each access then evicts the line the next one needs: cachegrind
// counted 10.6 L1 read misses per sphere and step in that loop, where two or three are needed.
// Spreading the starts over the 64 sets of a page removes those conflict misses. The offset is
// derived from the block's page address (no shared state), so it differs between arrays in
// practice and costs at most one page per array.
#include <cstddef>
#include <cstdint>
#include <new>

namespace shapepress::simulate {

template <class T>
struct StaggeredAllocator {
  using value_type = T;
  static constexpr std::size_t line = 64, page = 4096;
  static_assert(alignof(T) <= line);

  StaggeredAllocator() = default;
  template <class U>
  StaggeredAllocator(const StaggeredAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < page) return static_cast<T*>(::operator new(bytes));  // small: no set pressure
    std::byte* block = static_cast<std::byte*>(::operator new(bytes + page + line));
    const auto address = reinterpret_cast<std::uintptr_t>(block);
    // A multiplicative hash of the page number picks one of the 64 lines of a page; the first
    // line is kept for the block's own address (read back by deallocate).
    const std::size_t lines = page / line;
    const std::size_t pick = 1 + ((address / page) * 0x9E3779B97F4A7C15ULL >> 58) % (lines - 1);
    std::byte* aligned = block + (line - address % line) % line;
    std::byte* start = aligned + pick * line;
    reinterpret_cast<std::byte**>(start)[-1] = block;
    return reinterpret_cast<T*>(start);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < page) {
      ::operator delete(p);
      return;
    }
    ::operator delete(reinterpret_cast<std::byte**>(p)[-1]);
  }
  friend bool operator==(const StaggeredAllocator&, const StaggeredAllocator&) { return true; }
};

}  // namespace shapepress::simulate
