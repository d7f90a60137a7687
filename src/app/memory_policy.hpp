#pragma once
// How the programs that read whole sessions (hrg-report, hrg-bench, hrg-estimate) ask glibc's
// allocator to keep what they free. A session is read run by run: each run's text and arrays
// (megabytes) are freed and the next run's allocated at once. By default glibc returns such blocks
// to the kernel (mmap above its threshold, trimming the heap's top) and the next run faults every
// page in again: a third of the report's time went to page faults and zeroing (docs/measurements/
// 2026-11-27-report-speed.md). Kept, the next run reuses the same pages.

namespace hrgbench::app {

// Sets glibc's mmap threshold to its largest (32 MiB on 64-bit: a run's arrays come from the heap)
// and its trim threshold to 1 GiB (freed memory stays in the process). Peak memory is unchanged
// (what is kept is reused before anything new is asked of the kernel); only what the process holds
// after a peak. Call once, first thing in main, before any thread starts.
void KeepFreedMemoryForReuse() noexcept;

}  // namespace hrgbench::app
