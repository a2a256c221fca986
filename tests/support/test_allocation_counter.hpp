// Counting heap allocations in a test executable.
//
// The counters only count while `counting` is set, i.e. around the measured call. What they see
// depends on what the test file replaces; it opts in by defining, before including this header,
//   NMDP_COUNT_OPERATOR_NEW  replace the global operator new / delete family (std::vector,
//                            std::string, ...): counted in new_calls;
//   NMDP_COUNT_MALLOC        on glibc, interpose malloc / calloc / realloc / memalign /
//                            posix_memalign / aligned_alloc and forward them to the __libc_*
//                            entry points (Eigen allocates its dynamic matrices with std::malloc,
//                            and libstdc++'s operator new calls malloc): counted in malloc_calls.
// The replacements are definitions: exactly one translation unit of a test executable may include
// this header with either macro defined (every test executable is one .cpp file).
// Under AddressSanitizer (or another sanitizer with its own allocator), which owns malloc, the
// malloc family is counted through the sanitizer's allocation hook instead of by interposition.
// NMDP_COUNTS_MALLOC is 1 when the malloc family is really counted (NMDP_COUNT_MALLOC defined, on
// glibc or under such a sanitizer), else 0.
#pragma once
#include <atomic>
#include <cstdlib>
#include <new>

namespace nmdp::test::alloc {

inline std::atomic<bool> counting{false};
inline std::atomic<long> new_calls{0};     // operator new / new[] (all overloads)
inline std::atomic<long> malloc_calls{0};  // malloc family (includes the mallocs behind operator new)

inline void noteNew() {
  if (counting.load(std::memory_order_relaxed)) new_calls.fetch_add(1, std::memory_order_relaxed);
}
inline void noteMalloc() {
  if (counting.load(std::memory_order_relaxed)) malloc_calls.fetch_add(1, std::memory_order_relaxed);
}

inline void* countedNew(std::size_t size) {
  noteNew();
  if (size == 0) size = 1;
  if (void* p = std::malloc(size)) return p;
  throw std::bad_alloc();
}
inline void* countedAlignedNew(std::size_t size, std::size_t alignment) {
  noteNew();
  if (size == 0) size = 1;
  void* p = nullptr;
  if (alignment < sizeof(void*)) alignment = sizeof(void*);
  if (posix_memalign(&p, alignment, size) != 0) throw std::bad_alloc();
  return p;
}

}  // namespace nmdp::test::alloc

namespace nmdp::test {

struct AllocationCount {
  long news = 0, mallocs = 0;
  long total() const { return news + mallocs; }
};

// The allocations of one call of f().
template <class F>
AllocationCount countAllocations(F&& f) {
  alloc::new_calls = 0;
  alloc::malloc_calls = 0;
  alloc::counting = true;
  f();
  alloc::counting = false;
  return {alloc::new_calls.load(), alloc::malloc_calls.load()};
}

// Warm-up call, then one counted call.
template <class F>
AllocationCount allocationsOf(F&& f) {
  f();
  return countAllocations(f);
}

}  // namespace nmdp::test

// --- operator new / delete --------------------------------------------------------------------
#ifdef NMDP_COUNT_OPERATOR_NEW
void* operator new(std::size_t size) { return nmdp::test::alloc::countedNew(size); }
void* operator new[](std::size_t size) { return nmdp::test::alloc::countedNew(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return nmdp::test::alloc::countedNew(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return nmdp::test::alloc::countedNew(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t size, std::align_val_t al) {
  return nmdp::test::alloc::countedAlignedNew(size, static_cast<std::size_t>(al));
}
void* operator new[](std::size_t size, std::align_val_t al) {
  return nmdp::test::alloc::countedAlignedNew(size, static_cast<std::size_t>(al));
}
void* operator new(std::size_t size, std::align_val_t al, const std::nothrow_t&) noexcept {
  try {
    return nmdp::test::alloc::countedAlignedNew(size, static_cast<std::size_t>(al));
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, std::align_val_t al, const std::nothrow_t&) noexcept {
  try {
    return nmdp::test::alloc::countedAlignedNew(size, static_cast<std::size_t>(al));
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
#endif  // NMDP_COUNT_OPERATOR_NEW

// --- the malloc family (glibc: interpose and forward to the __libc_* entry points) -----------
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define NMDP_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define NMDP_SANITIZED 1
#endif
#if defined(NMDP_COUNT_MALLOC) && defined(NMDP_SANITIZED)
// The sanitizer owns malloc: its hook sees every allocation its allocator serves (the mallocs
// behind operator new included, as with the interposition below). The hook must not allocate.
#include <sanitizer/allocator_interface.h>
#define NMDP_COUNTS_MALLOC 1
namespace nmdp::test::alloc {
inline void sanitizerMallocHook(const volatile void*, std::size_t) { noteMalloc(); }
inline void sanitizerFreeHook(const volatile void*) {}
[[maybe_unused]] static const int sanitizer_hooks_installed =
    __sanitizer_install_malloc_and_free_hooks(sanitizerMallocHook, sanitizerFreeHook);
}  // namespace nmdp::test::alloc
#elif defined(NMDP_COUNT_MALLOC) && defined(__GLIBC__)
#define NMDP_COUNTS_MALLOC 1
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);

void* malloc(std::size_t size) {
  nmdp::test::alloc::noteMalloc();
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  nmdp::test::alloc::noteMalloc();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) {
  nmdp::test::alloc::noteMalloc();
  return __libc_realloc(p, size);
}
void free(void* p) { __libc_free(p); }
void* memalign(std::size_t alignment, std::size_t size) {
  nmdp::test::alloc::noteMalloc();
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) {
  nmdp::test::alloc::noteMalloc();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  nmdp::test::alloc::noteMalloc();
  if (alignment < sizeof(void*) || (alignment & (alignment - 1)) != 0) return 22;  // EINVAL
  void* p = __libc_memalign(alignment, size);
  if (!p) return 12;  // ENOMEM
  *out = p;
  return 0;
}
}
#else
#define NMDP_COUNTS_MALLOC 0
#endif
