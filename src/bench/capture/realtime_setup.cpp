#include "hrgbench/bench/capture/realtime_setup.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <string>

namespace hrgbench::bench {
namespace {

// "EPERM (Operation not permitted)". strerrorname_np/strerrordesc_np (glibc ≥ 2.32) are
// thread-safe, unlike strerror.
std::string ErrorText(int error_number) {
  const char* name = strerrorname_np(error_number);
  const char* desc = strerrordesc_np(error_number);
  return std::string(name != nullptr ? name : "E?") + " (" +
         (desc != nullptr ? desc : "unknown error " + std::to_string(error_number)) + ")";
}

std::string LimitText(int resource) {
  rlimit limit{};
  if (getrlimit(resource, &limit) != 0) return "unknown";
  if (limit.rlim_cur == RLIM_INFINITY) return "unlimited";
  return std::to_string(limit.rlim_cur);
}

RealtimeItem Refused(int error_number, const std::string& why) {
  RealtimeItem item;
  item.grant = RealtimeGrant::kRefused;
  item.error_number = error_number;
  item.reason = ErrorText(error_number);
  if (!why.empty()) item.reason += ": " + why;
  return item;
}

RealtimeItem Granted() {
  RealtimeItem item;
  item.grant = RealtimeGrant::kGranted;
  return item;
}

RealtimeItem ApplyScheduling(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  // pthread_* return the error number instead of setting errno.
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (rc == 0) return Granted();
  std::string why;
  if (rc == EPERM) {
    why = "needs CAP_SYS_NICE or RLIMIT_RTPRIO >= " + std::to_string(priority) + " (soft limit " +
          LimitText(RLIMIT_RTPRIO) + ")";
  } else if (rc == EINVAL) {
    why = "priority " + std::to_string(priority) + " outside SCHED_FIFO's " +
          std::to_string(sched_get_priority_min(SCHED_FIFO)) + ".." +
          std::to_string(sched_get_priority_max(SCHED_FIFO));
  }
  return Refused(rc, why);
}

RealtimeItem ApplyAffinity(int cpu) {
  if (cpu >= CPU_SETSIZE) {
    return Refused(EINVAL,
                   "CPU " + std::to_string(cpu) + " >= CPU_SETSIZE " + std::to_string(CPU_SETSIZE));
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(static_cast<std::size_t>(cpu), &set);
  const int rc = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
  if (rc == 0) return Granted();
  std::string why;
  if (rc == EINVAL) {
    why = "CPU " + std::to_string(cpu) + " is not online or not in this process's cpuset (" +
          std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " CPUs online)";
  }
  return Refused(rc, why);
}

// Touches every page of a stack frame of kStackPrefaultBytes, so the capture loop's stack is
// resident (and, after mlockall, locked) before the first sample. noinline: the frame must really
// exist; volatile: the stores must really happen.
[[gnu::noinline]] void PrefaultStack() noexcept {
  volatile unsigned char frame[realtime_internal::kStackPrefaultBytes];
  constexpr std::size_t kPage = 4096;  // the smallest page size on Linux targets we run on
  for (std::size_t i = 0; i < sizeof(frame); i += kPage) frame[i] = 0;
  frame[sizeof(frame) - 1] = 0;
}

std::mutex memory_lock_mutex;
pid_t memory_locked_pid = 0;  // guarded by memory_lock_mutex

}  // namespace

bool RealtimeReport::AllGranted() const noexcept {
  return scheduling.grant != RealtimeGrant::kRefused && affinity.grant != RealtimeGrant::kRefused &&
         memory_lock.grant != RealtimeGrant::kRefused;
}

std::string RealtimeReport::Summary() const {
  auto item_text = [](const std::string& what, const RealtimeItem& item) {
    std::string text = what + " " + std::string(ToString(item.grant));
    if (item.grant == RealtimeGrant::kRefused) text += ": " + item.reason;
    return text;
  };
  std::string text;
  if (requested.priority != 0) {
    text += item_text("SCHED_FIFO " + std::to_string(requested.priority), scheduling);
  } else {
    text += "SCHED_FIFO not requested";
  }
  text += "; ";
  if (requested.cpu >= 0) {
    text += item_text("CPU " + std::to_string(requested.cpu), affinity);
  } else {
    text += "CPU any";
  }
  text += "; ";
  text += requested.lock_memory ? item_text("mlockall", memory_lock) : "mlockall not requested";
  text += "; stack " + std::to_string(stack_prefault_bytes / 1024) + " KiB prefaulted";
  if (!applied) text += "; (capture thread setup did not run)";
  return text;
}

RealtimeItem LockProcessMemory() {
  std::lock_guard lock(memory_lock_mutex);
  // Memory locks are not inherited by a fork()ed child: remember the outcome per process.
  if (memory_locked_pid == getpid()) return Granted();
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
    memory_locked_pid = getpid();
    return Granted();
  }
  const int error_number = errno;
  std::string why;
  if (error_number == EPERM) {
    why = "needs CAP_IPC_LOCK or RLIMIT_MEMLOCK > 0 (soft limit " + LimitText(RLIMIT_MEMLOCK) +
          " bytes)";
  } else if (error_number == ENOMEM) {
    why = "the process's mappings exceed RLIMIT_MEMLOCK (soft limit " + LimitText(RLIMIT_MEMLOCK) +
          " bytes) and there is no CAP_IPC_LOCK";
  }
  return Refused(error_number, why);
}

namespace realtime_internal {

void ApplyToCallingThread(const RealtimeOptions& options, RealtimeReport& report) {
  report.requested = options;
  if (options.cpu >= 0) report.affinity = ApplyAffinity(options.cpu);
  if (options.priority != 0) report.scheduling = ApplyScheduling(options.priority);
  PrefaultStack();
  report.stack_prefault_bytes = kStackPrefaultBytes;

  // Read back: the record states what the thread runs with, not only what the calls returned.
  sched_param param{};
  int policy = -1;
  if (pthread_getschedparam(pthread_self(), &policy, &param) == 0) {
    report.policy = policy;
    report.thread_priority = param.sched_priority;
  }
  if (report.scheduling.grant == RealtimeGrant::kGranted &&
      (policy != SCHED_FIFO || param.sched_priority != options.priority)) {
    report.scheduling =
        Refused(EINVAL, "read-back policy " + std::to_string(policy) + " priority " +
                            std::to_string(param.sched_priority) + " differs from the request");
  }
  report.cpu_at_start = sched_getcpu();
  report.applied = true;
}

}  // namespace realtime_internal
}  // namespace hrgbench::bench
