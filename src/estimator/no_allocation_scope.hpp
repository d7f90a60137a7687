#pragma once
// Marks a sample loop that must not allocate. In the checked build of the library (compiled with
// EIGEN_RUNTIME_NO_MALLOC and assertions on, used by tests/unit/estimator/allocation_test.cpp) any
// Eigen heap allocation inside the scope aborts; in normal builds this is empty. Eigen's flag is
// one global, so the checked build is exercised single-threaded.
//
// Internal to the estimator library.

#include <Eigen/Core>

namespace hrgbench::estimator::internal {

class NoAllocationScope {
 public:
#ifdef EIGEN_RUNTIME_NO_MALLOC
  NoAllocationScope() : previous_(Eigen::internal::is_malloc_allowed()) {
    Eigen::internal::set_is_malloc_allowed(false);
  }
  ~NoAllocationScope() { Eigen::internal::set_is_malloc_allowed(previous_); }

 private:
  bool previous_;
#else
  // User-provided (not defaulted) so that an unused-variable warning does not fire in normal
  // builds.
  NoAllocationScope() {}
  ~NoAllocationScope() {}
#endif
  NoAllocationScope(const NoAllocationScope&) = delete;
  NoAllocationScope& operator=(const NoAllocationScope&) = delete;
};

}  // namespace hrgbench::estimator::internal
