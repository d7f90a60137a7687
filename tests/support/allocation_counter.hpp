#pragma once
// Counts heap allocations, to prove a real-time path does not allocate (STYLE rule 3): those of
// the calling thread (AllocationScope) and those of the whole process (process_allocation_count,
// for code that allocates on worker threads). Replaces the global operator new: include this
// header in EXACTLY ONE translation unit of a test binary (replacement functions may not be
// inline). new[] and delete[] are the standard's defaults, which call these.
//
//   hrgbench::testing::AllocationScope scope;
//   ... code under test ...
//   EXPECT_EQ(scope.Count(), 0);

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace hrgbench::testing {

inline thread_local std::int64_t thread_allocation_count = 0;
inline std::atomic<std::int64_t> process_allocation_count{0};

class AllocationScope {
 public:
  AllocationScope() : start_(thread_allocation_count) {}
  std::int64_t Count() const { return thread_allocation_count - start_; }

 private:
  std::int64_t start_;
};

}  // namespace hrgbench::testing

// GCC sees free() on memory from operator new once these are inlined and warns; here that pairing
// is exactly what is intended.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  ++hrgbench::testing::thread_allocation_count;
  hrgbench::testing::process_allocation_count.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t alignment) {
  ++hrgbench::testing::thread_allocation_count;
  hrgbench::testing::process_allocation_count.fetch_add(1, std::memory_order_relaxed);
  const auto align = static_cast<std::size_t>(alignment);
  const std::size_t rounded = (size + align - 1) / align * align;
  if (void* p = std::aligned_alloc(align, rounded == 0 ? align : rounded)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop
