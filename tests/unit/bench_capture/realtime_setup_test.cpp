// Real-time setup of the capture thread: whatever the system grants, the report must say exactly
// that, and the capture must run either way.
//
// Runs that change process-wide state (mlockall, rlimits, capabilities) run in a fork()ed child,
// so this test process stays as it was; the child reports its findings through a pipe. The
// capture thread's view is taken from inside it (FakeGyroElectronics::ReadSamples records
// sched_getscheduler(0) and sched_getcpu() of the calling thread).
//
// Here (CI, containers) the tests often run as root with CAP_SYS_NICE and CAP_IPC_LOCK: then
// SCHED_FIFO and mlockall are granted. The refusal test therefore drops those two capabilities
// from the child's effective set and lowers RLIMIT_RTPRIO and RLIMIT_MEMLOCK to 0, which makes
// the kernel refuse with EPERM as it would for an unprivileged operator account. Requests that no
// privilege can grant (priority 100: EINVAL; a CPU that does not exist) are tested in-process.

#include <gtest/gtest.h>
#include <linux/capability.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "fake_gyro_electronics.hpp"
#include "hrgbench/bench/capture/capture.hpp"

namespace hrgbench::bench {
namespace {

using testing::FakeGyroElectronics;

struct ObservedRun {
  RealtimeReport report;
  CaptureResult result;
  int policy_in_thread = -1;
  int cpu_in_thread = -1;
};

ObservedRun CaptureWith(const RealtimeOptions& options) {
  hw::ManualClock clock(0);
  FakeGyroElectronics fake(clock, {});
  SampleRing ring(4096);
  CaptureRun run;
  run.sample_count = 2000;
  run.clock = &clock;
  run.realtime = options;
  CaptureThread capture;
  ObservedRun observed;
  auto started = capture.Start(fake, ring, run);
  if (started) observed.report = *started;
  observed.result = capture.Join();
  observed.policy_in_thread = fake.observed_policy;
  observed.cpu_in_thread = fake.observed_cpu;
  return observed;
}

// Locked memory of this process in kB (/proc/self/status VmLck).
long LockedKb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmLck:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

// Runs `body` in a fork()ed child; returns what it wrote (its findings), or a failure note.
std::string InChild(const std::function<std::string()>& body) {
  int fds[2];
  if (pipe(fds) != 0) return "FAIL: pipe";
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const std::string text = body();
    const char* p = text.data();
    std::size_t left = text.size();
    while (left > 0) {
      const ssize_t n = write(fds[1], p, left);
      if (n <= 0) break;
      p += n;
      left -= static_cast<std::size_t>(n);
    }
    _exit(0);  // no gtest teardown, no static destructors in the child
  }
  close(fds[1]);
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = read(fds[0], buffer, sizeof(buffer))) > 0;) {
    text.append(buffer, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) text += "\nFAIL: child did not exit cleanly";
  return text;
}

// Every rule a report must obey, whatever was granted; one "FAIL: ..." line per broken rule.
std::string CheckCoherent(const ObservedRun& o, long locked_kb) {
  std::ostringstream fail;
  const RealtimeReport& r = o.report;
  if (!r.applied) fail << "FAIL: setup not applied\n";
  if (o.result.termination != CaptureTermination::kCountReached) {
    fail << "FAIL: capture did not complete: " << ToString(o.result.termination) << "\n";
  }
  if (o.result.realtime.Summary() != r.Summary()) fail << "FAIL: result and Start disagree\n";
  auto refused_with_reason = [&fail](const char* what, const RealtimeItem& item) {
    if (item.grant == RealtimeGrant::kRefused && (item.reason.empty() || item.error_number == 0)) {
      fail << "FAIL: " << what << " refused without a reason\n";
    }
  };
  refused_with_reason("scheduling", r.scheduling);
  refused_with_reason("affinity", r.affinity);
  refused_with_reason("memory lock", r.memory_lock);
  if (r.requested.priority != 0) {
    const bool granted = r.scheduling.grant == RealtimeGrant::kGranted;
    if (r.scheduling.grant == RealtimeGrant::kNotRequested) fail << "FAIL: scheduling not tried\n";
    if (granted != (o.policy_in_thread == SCHED_FIFO)) {
      fail << "FAIL: scheduling " << ToString(r.scheduling.grant) << " but the thread runs policy "
           << o.policy_in_thread << "\n";
    }
    if (granted && r.thread_priority != r.requested.priority) fail << "FAIL: priority read-back\n";
  }
  if (r.requested.cpu >= 0 && r.affinity.grant == RealtimeGrant::kGranted &&
      o.cpu_in_thread != r.requested.cpu) {
    fail << "FAIL: pinned to " << r.requested.cpu << " but ran on " << o.cpu_in_thread << "\n";
  }
  if (r.requested.lock_memory) {
    const bool granted = r.memory_lock.grant == RealtimeGrant::kGranted;
    if (granted != (locked_kb > 0)) {
      fail << "FAIL: mlockall " << ToString(r.memory_lock.grant) << " but VmLck " << locked_kb
           << " kB\n";
    }
  }
  return fail.str();
}

TEST(RealtimeSetupTest, NothingRequestedNothingChanged) {
  const ObservedRun o = CaptureWith({});
  EXPECT_TRUE(o.report.applied);
  EXPECT_EQ(o.report.scheduling.grant, RealtimeGrant::kNotRequested);
  EXPECT_EQ(o.report.affinity.grant, RealtimeGrant::kNotRequested);
  EXPECT_EQ(o.report.memory_lock.grant, RealtimeGrant::kNotRequested);
  EXPECT_TRUE(o.report.AllGranted());
  EXPECT_EQ(o.policy_in_thread, SCHED_OTHER);
  EXPECT_EQ(o.report.policy, SCHED_OTHER);
  EXPECT_EQ(o.report.stack_prefault_bytes, realtime_internal::kStackPrefaultBytes);
  EXPECT_EQ(o.report.Summary(),
            "SCHED_FIFO not requested; CPU any; mlockall not requested; stack 128 KiB prefaulted");
}

TEST(RealtimeSetupTest, Priority10AndLockedMemoryAreReportedAsTheyAre) {
  const std::string findings = InChild([] {
    RealtimeOptions options;
    options.priority = 10;
    options.cpu = 0;
    options.lock_memory = true;
    const ObservedRun o = CaptureWith(options);
    return CheckCoherent(o, LockedKb()) + "summary: " + o.report.Summary();
  });
  EXPECT_EQ(findings.find("FAIL"), std::string::npos) << findings;
  std::printf("[ info ] as this process is permitted: %s\n", findings.c_str());
}

// Drops capabilities from the calling process's effective set (always allowed: a subset).
bool DropEffectiveCapabilities(std::initializer_list<int> capabilities) {
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct data[2]{};
  if (syscall(SYS_capget, &header, data) != 0) return false;
  for (int cap : capabilities) data[cap / 32].effective &= ~(1u << (cap % 32));
  return syscall(SYS_capset, &header, data) == 0;
}

TEST(RealtimeSetupTest, WithoutPrivilegeEverythingIsRefusedWithItsReasonAndTheCaptureRuns) {
  const std::string findings = InChild([] {
    std::ostringstream out;
    if (!DropEffectiveCapabilities({CAP_SYS_NICE, CAP_IPC_LOCK})) out << "FAIL: capset\n";
    const rlimit zero{0, 0};
    if (setrlimit(RLIMIT_RTPRIO, &zero) != 0 || setrlimit(RLIMIT_MEMLOCK, &zero) != 0) {
      out << "FAIL: setrlimit\n";
    }
    RealtimeOptions options;
    options.priority = 10;
    options.lock_memory = true;
    const ObservedRun o = CaptureWith(options);
    out << CheckCoherent(o, LockedKb());
    if (o.report.scheduling.grant != RealtimeGrant::kRefused ||
        o.report.scheduling.error_number != EPERM ||
        o.report.scheduling.reason.find("RLIMIT_RTPRIO >= 10 (soft limit 0)") ==
            std::string::npos) {
      out << "FAIL: scheduling should be refused with EPERM and the rule: "
          << o.report.scheduling.reason << "\n";
    }
    if (o.report.memory_lock.grant != RealtimeGrant::kRefused ||
        o.report.memory_lock.error_number != EPERM ||
        o.report.memory_lock.reason.find("CAP_IPC_LOCK") == std::string::npos) {
      out << "FAIL: mlockall should be refused with EPERM: " << o.report.memory_lock.reason << "\n";
    }
    if (o.policy_in_thread != SCHED_OTHER) out << "FAIL: thread not SCHED_OTHER\n";
    if (o.report.AllGranted()) out << "FAIL: AllGranted\n";
    if (o.result.samples_pushed != 2000) out << "FAIL: capture incomplete\n";
    out << "summary: " << o.report.Summary();
    return out.str();
  });
  EXPECT_EQ(findings.find("FAIL"), std::string::npos) << findings;
  EXPECT_NE(findings.find("SCHED_FIFO 10 refused: EPERM (Operation not permitted)"),
            std::string::npos)
      << findings;
  std::printf("[ info ] unprivileged: %s\n", findings.c_str());
}

TEST(RealtimeSetupTest, AMemlockLimitSmallerThanTheProcessIsEnomem) {
  const std::string findings = InChild([] {
    std::ostringstream out;
    if (!DropEffectiveCapabilities({CAP_IPC_LOCK})) out << "FAIL: capset\n";
    const rlimit small{64 * 1024, 64 * 1024};  // a typical distribution default
    if (setrlimit(RLIMIT_MEMLOCK, &small) != 0) out << "FAIL: setrlimit\n";
    const RealtimeItem item = LockProcessMemory();
    if (item.grant != RealtimeGrant::kRefused || item.error_number != ENOMEM ||
        item.reason.find("exceed RLIMIT_MEMLOCK (soft limit 65536 bytes)") == std::string::npos) {
      out << "FAIL: expected ENOMEM with the limit: " << item.reason << "\n";
    }
    return out.str();
  });
  EXPECT_EQ(findings.find("FAIL"), std::string::npos) << findings;
}

TEST(RealtimeSetupTest, ImpossibleRequestsAreRefusedWithEinvalWhateverThePrivilege) {
  RealtimeOptions options;
  options.priority = 100;  // SCHED_FIFO is 1..99
  options.cpu = 1000;      // < CPU_SETSIZE, but no such CPU here
  const ObservedRun o = CaptureWith(options);
  EXPECT_EQ(o.result.termination, CaptureTermination::kCountReached);
  EXPECT_EQ(o.report.scheduling.grant, RealtimeGrant::kRefused);
  EXPECT_EQ(o.report.scheduling.error_number, EINVAL);
  EXPECT_NE(o.report.scheduling.reason.find("outside SCHED_FIFO's 1..99"), std::string::npos)
      << o.report.scheduling.reason;
  EXPECT_EQ(o.report.affinity.grant, RealtimeGrant::kRefused);
  EXPECT_EQ(o.report.affinity.error_number, EINVAL);
  EXPECT_NE(o.report.affinity.reason.find("CPU 1000"), std::string::npos);
  EXPECT_EQ(o.policy_in_thread, SCHED_OTHER);
  EXPECT_EQ(CheckCoherent(o, LockedKb()), "");
  options.cpu = 5000;  // beyond CPU_SETSIZE: refused before the call
  EXPECT_EQ(CaptureWith(options).report.affinity.error_number, EINVAL);
}

}  // namespace
}  // namespace hrgbench::bench
