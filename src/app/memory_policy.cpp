#include "app/memory_policy.hpp"

#include <malloc.h>

namespace hrgbench::app {

void KeepFreedMemoryForReuse() noexcept {
  // glibc's DEFAULT_MMAP_THRESHOLD_MAX on 64-bit; a larger value is refused (mallopt returns 0).
  constexpr int kMmapThresholdBytes = 32 * 1024 * 1024;
  constexpr int kTrimThresholdBytes = 1024 * 1024 * 1024;
  // Failure only keeps glibc's defaults (slower, not wrong): nothing to report.
  (void)::mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes);
  (void)::mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes);
}

}  // namespace hrgbench::app
