#pragma once
// Real-time setup of the capture thread: SCHED_FIFO priority, CPU affinity, locked memory and a
// prefaulted stack — each requested by the station config ([realtime]), each granted or refused by
// the operating system, and each outcome reported exactly (what, and why not), so the session
// record can say under which conditions its samples were captured (issue 4, section 3).
//
// A refusal is an expected condition, not an error: the capture runs anyway, with what it got.
//
// Linux rules that decide (man 7 sched, man 2 mlock):
//  - SCHED_FIFO needs CAP_SYS_NICE, or an RLIMIT_RTPRIO soft limit ≥ the priority (else EPERM);
//    a priority outside sched_get_priority_min/max(SCHED_FIFO) = 1..99 is EINVAL.
//  - mlockall needs CAP_IPC_LOCK, or an RLIMIT_MEMLOCK large enough for everything mapped now
//    (MCL_CURRENT; else ENOMEM, or EPERM if the limit is 0). With MCL_FUTURE every later mapping
//    is locked and populated at once, and without CAP_IPC_LOCK a later mapping beyond the limit
//    FAILS (std::bad_alloc from operator new): request it only with the capability or a large
//    limit. Memory locks are process-wide and not inherited across fork().
//  - Affinity to a CPU that does not exist or is not in the process's cpuset is EINVAL.
//
// Threads and real-time safety: setup functions, called before the real-time loop, never in it.
// They allocate (the reason strings) and make system calls.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace hrgbench::bench {

struct RealtimeOptions {
  // SCHED_FIFO priority of the capture thread: 1..99, 0 = off (keep the inherited policy,
  // normally SCHED_OTHER). Larger values are passed on and refused by the kernel (EINVAL,
  // reported): the config loader is where a range belongs, not here.
  int priority = 0;
  // Pin the capture thread to this CPU (0-based); -1 = any CPU. Keep the CPU free of other
  // real-time work; on a 2-core machine pinning mostly helps cache locality.
  int cpu = -1;
  // mlockall(MCL_CURRENT | MCL_FUTURE) once per process, in the thread that starts the capture,
  // before the capture thread exists, so page faults cannot stall the loop. See the warning above.
  bool lock_memory = false;
};

enum class RealtimeGrant : std::uint8_t {
  kNotRequested,  // the option was off
  kGranted,       // the system call succeeded (and, for scheduling, the read-back agrees)
  kRefused,       // the system call failed: see error_number and reason
};

constexpr std::string_view ToString(RealtimeGrant grant) noexcept {
  switch (grant) {
    case RealtimeGrant::kNotRequested:
      return "not requested";
    case RealtimeGrant::kGranted:
      return "granted";
    case RealtimeGrant::kRefused:
      return "refused";
  }
  return "?";
}

struct RealtimeItem {
  RealtimeGrant grant = RealtimeGrant::kNotRequested;
  int error_number = 0;  // errno (or the pthread return value) when refused, else 0
  std::string reason;    // when refused: "EPERM (Operation not permitted): <the rule that bit>"
};

// What the capture thread asked for and what it got. Sentinel defaults: applied = false means the
// thread never ran its setup (Start failed or was not called).
struct RealtimeReport {
  RealtimeOptions requested;
  RealtimeItem scheduling;               // SCHED_FIFO at requested.priority
  RealtimeItem affinity;                 // pinned to requested.cpu
  RealtimeItem memory_lock;              // mlockall(MCL_CURRENT | MCL_FUTURE)
  std::size_t stack_prefault_bytes = 0;  // stack touched at thread start (always done)
  // Read back inside the capture thread after setup (pthread_getschedparam, sched_getcpu).
  bool applied = false;
  int policy = -1;  // SCHED_OTHER (0), SCHED_FIFO (1), ...; -1 = not read
  int thread_priority = 0;
  int cpu_at_start = -1;

  // True when nothing requested was refused.
  bool AllGranted() const noexcept;
  // One line for the session record, e.g. "SCHED_FIFO 10 granted; CPU 1 granted; mlockall
  // granted; stack 128 KiB prefaulted" or "SCHED_FIFO 10 refused: EPERM (Operation not
  // permitted): needs CAP_SYS_NICE or RLIMIT_RTPRIO >= 10 (soft limit 0); ...".
  std::string Summary() const;
};

// Locks the process's memory (mlockall(MCL_CURRENT | MCL_FUTURE)) unless this process already
// did so successfully (the outcome is remembered per process id, so a fork()ed child tries
// again). Call from a non-real-time thread before starting the capture thread. Thread-safe.
RealtimeItem LockProcessMemory();

namespace realtime_internal {
// In the capture thread, before its loop: applies scheduling and affinity to the calling thread,
// prefaults kStackPrefaultBytes of its stack and reads back what it got. Fills every field of
// `report` except memory_lock. Used by CaptureThread; public for tests.
void ApplyToCallingThread(const RealtimeOptions& options, RealtimeReport& report);
inline constexpr std::size_t kStackPrefaultBytes = 128 * 1024;
}  // namespace realtime_internal

}  // namespace hrgbench::bench
