#include "malloc_guard.hpp"

#include <cstdlib>
#include <malloc.h>

namespace {
thread_local bool g_active = false;
thread_local std::size_t g_count = 0;
inline void note() {
  if (g_active) ++g_count;
}
}  // namespace

#if defined(__SANITIZE_ADDRESS__)
// Under AddressSanitizer (MBGEN_SANITIZE) the allocator is ASan's: count through its hooks
// rather than interposing malloc, which would hand ASan memory it did not allocate.
// (Declared here: GCC ships no sanitizer/allocator_interface.h, but its libasan has the hook.)
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*, std::size_t),
                                                         void (*free_hook)(const volatile void*));

namespace {
void on_malloc(const volatile void*, std::size_t) { note(); }
void on_free(const volatile void*) {}
const int g_hooks_installed = __sanitizer_install_malloc_and_free_hooks(on_malloc, on_free);
}  // namespace
#else
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
}

extern "C" {
void* malloc(std::size_t n) {
  note();
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) {
  note();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) {
  note();
  return __libc_realloc(p, n);
}
void* memalign(std::size_t alignment, std::size_t n) {
  note();
  return __libc_memalign(alignment, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) {
  note();
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  note();
  *out = __libc_memalign(alignment, n);
  return *out ? 0 : 12;  // ENOMEM
}
}
#endif

namespace mbgen::test {
MallocGuard::MallocGuard() {
  g_count = 0;
  g_active = true;
}
MallocGuard::~MallocGuard() { g_active = false; }
std::size_t MallocGuard::count() const { return g_count; }
}  // namespace mbgen::test
