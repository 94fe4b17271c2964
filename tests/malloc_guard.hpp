#pragma once
// A malloc guard (after Drake's limit_malloc): while a MallocGuard lives on this thread, every
// malloc, calloc, realloc and aligned allocation is counted. The hooks interpose glibc's
// allocator, so they see Eigen's and the C++ library's allocations alike. Link malloc_guard.cpp.
#include <cstddef>

namespace mbgen::test {

class MallocGuard {
 public:
  MallocGuard();
  ~MallocGuard();
  MallocGuard(const MallocGuard&) = delete;
  MallocGuard& operator=(const MallocGuard&) = delete;
  /// Allocations counted since this guard was made.
  std::size_t count() const;
};

}  // namespace mbgen::test
