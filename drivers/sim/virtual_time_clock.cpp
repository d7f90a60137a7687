#include "sim/virtual_time_clock.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

namespace hrgbench::drivers::sim_station {

namespace {
using WallClock = std::chrono::steady_clock;
constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();
// Paced time may run fast to make up this much lag (step overheads, a short stall) so that it
// keeps its scale on average, but no more: a longer stall is not made up.
constexpr auto kPacingCatchUp = std::chrono::milliseconds(20);

struct ThreadRecord {
  enum class State { kRunning, kWaiting, kParked };
  State state = State::kRunning;
  std::int64_t deadline_ns = 0;
  bool wake_on_output = false;
  std::uint64_t seen_epoch = 0;
  WallClock::time_point running_since = WallClock::now();
  // Running because output woke it (not a deadline): time may go on up to the lookahead.
  bool woken_by_output = false;
  std::int64_t woken_at_ns = 0;
  pid_t tid = 0;  // the kernel's id of the thread, to ask whether it is blocked (see MayPark)
  // Inside Wait: once woken (kRunning) it is only re-taking the clock's lock to return, which
  // its kernel state shows as 'S' while another thread holds it: never parked then.
  bool in_wait = false;
};

// True unless the kernel says the thread is runnable ('R': running, or waiting for a CPU on a
// loaded machine) or in uninterruptible I/O ('D': fsync, a page fault): such a thread is working
// and will wait on the clock again, so time must wait for it. Only a thread asleep off the clock
// ('S': join, a mutex, a condition variable) is parked. Where /proc cannot tell, park as before.
bool MayPark(pid_t tid) {
  if (tid <= 0) return true;
  std::ifstream stat("/proc/self/task/" + std::to_string(tid) + "/stat");
  std::string line;
  if (!stat || !std::getline(stat, line)) return true;
  // "tid (comm) S ...": comm may hold spaces and parentheses; the state follows the last ')'.
  const std::size_t close = line.rfind(')');
  if (close == std::string::npos || close + 2 >= line.size()) return true;
  const char state = line[close + 2];
  return state != 'R' && state != 'D';
}
}  // namespace

struct VirtualTimeClock::Core {
  explicit Core(const VirtualTimeClockOptions& o) : options(o), now_ns(o.start_ns) {}

  // Locks `mutex` for a thread coming to the clock. While it waits for the lock its kernel state
  // is 'S' (a futex), which the park check (run with the lock held) would read as "blocked
  // elsewhere" and park a thread that is only queueing for the clock itself: so it is counted as
  // entering, and no thread is parked while one is (the check looks again a park period later).
  std::unique_lock<std::mutex> Enter() {
    entering.fetch_add(1, std::memory_order_acq_rel);
    std::unique_lock lock(mutex);
    entering.fetch_sub(1, std::memory_order_acq_rel);
    return lock;
  }

  void Detach(std::thread::id id) {
    {
      const auto lock = Enter();
      threads.erase(id);
    }
    cv.notify_all();  // the remaining threads may all be waiting now
  }
  // True when no running thread forbids moving time to `next_ns`.
  bool MayAdvanceTo(std::int64_t next_ns) const {
    return std::none_of(threads.begin(), threads.end(), [&](const auto& entry) {
      const ThreadRecord& r = entry.second;
      return r.state == ThreadRecord::State::kRunning &&
             (!r.woken_by_output || next_ns > r.woken_at_ns + options.output_lookahead_ns);
    });
  }
  // Marks the waiters that may go as running; true if any. Requires mutex.
  bool WakeDue(std::uint64_t current_epoch) {
    const std::int64_t now = now_ns.load(std::memory_order_relaxed);
    bool woke = false;
    for (auto& [id, record] : threads) {
      if (record.state != ThreadRecord::State::kWaiting) continue;
      const bool deadline = record.deadline_ns <= now;
      if (deadline || (record.wake_on_output && record.seen_epoch != current_epoch)) {
        record.state = ThreadRecord::State::kRunning;
        record.running_since = WallClock::now();
        record.woken_by_output = !deadline;
        record.woken_at_ns = now;
        woke = true;
      }
    }
    return woke;
  }
  // One step: to the next event, serving the participants due then. False (nothing done) when a
  // running thread forbids it. Requires mutex (held by `lock`); may release it while pacing.
  bool AdvanceOnce(std::unique_lock<std::mutex>& lock);

  const VirtualTimeClockOptions options;
  std::mutex mutex;
  std::atomic<int> entering{0};  // threads waiting for `mutex` in Enter()
  std::condition_variable cv;
  std::atomic<std::int64_t> now_ns;
  std::atomic<std::uint64_t> epoch{0};
  bool pacing = false;  // a thread is waiting for the wall clock to catch up (mutex released)
  // Pacing reference: simulated anchor_sim_ns corresponds to wall time anchor_wall. Set at the
  // first advance (not at construction: a station that takes a while to build must not then run
  // ahead to "catch up") and moved forward whenever the simulation falls behind the wall clock
  // by more than kPacingCatchUp.
  bool anchored = false;
  WallClock::time_point anchor_wall;
  std::int64_t anchor_sim_ns = 0;
  std::map<std::thread::id, ThreadRecord> threads;
  std::vector<sim::SimulationParticipant*> participants;
  VirtualTimeClockStatistics statistics;
};

namespace {
// Detaches the thread from every clock it waited on when it exits, so a finished capture thread
// does not hold simulated time back. Weak references: a clock may be gone by then.
struct ThreadAttachments {
  std::vector<std::weak_ptr<VirtualTimeClock::Core>> cores;
  ~ThreadAttachments() {
    const std::thread::id id = std::this_thread::get_id();
    for (auto& weak : cores) {
      if (auto core = weak.lock()) core->Detach(id);
    }
  }
};
thread_local ThreadAttachments t_attachments;
}  // namespace

bool VirtualTimeClock::Core::AdvanceOnce(std::unique_lock<std::mutex>& lock) {
  const std::int64_t now = now_ns.load(std::memory_order_relaxed);
  std::int64_t next = kNever;
  for (const auto& [id, record] : threads) {
    if (record.state == ThreadRecord::State::kWaiting) next = std::min(next, record.deadline_ns);
  }
  for (sim::SimulationParticipant* p : participants) {
    next = std::min(next, std::max(p->NextEventNs(), now));
  }
  if (next == kNever || !MayAdvanceTo(next)) return false;
  if (options.time_scale > 0.0 && next > now) {
    const WallClock::time_point wall_now = WallClock::now();
    const auto wall_at = [&](std::int64_t sim_ns) {
      return anchor_wall + std::chrono::nanoseconds(static_cast<std::int64_t>(
                               static_cast<double>(sim_ns - anchor_sim_ns) / options.time_scale));
    };
    // First advance, or already late for `next` by more than the catch-up allowance (a slow
    // machine, or the threads worked off the clock for a while): pace the step from here.
    if (!anchored || wall_now > wall_at(next) + kPacingCatchUp) {
      anchored = true;
      anchor_wall = wall_now;
      anchor_sim_ns = now;
    }
    const WallClock::time_point wall_target = wall_at(next);
    if (wall_now < wall_target) {
      pacing = true;
      cv.wait_until(lock, wall_target);
      pacing = false;
      return true;  // the caller re-evaluates: someone may have come or gone meanwhile
    }
  }
  now_ns.store(next, std::memory_order_release);
  ++statistics.advances;
  bool output = false;
  for (sim::SimulationParticipant* p : participants) {
    if (p->NextEventNs() > next) continue;
    ++statistics.services;
    output = p->Service(next) || output;
  }
  if (output) {
    epoch.fetch_add(1, std::memory_order_acq_rel);
    ++statistics.outputs;
  }
  if (WakeDue(epoch.load(std::memory_order_acquire))) cv.notify_all();
  return true;
}

bool VirtualTimeClockOptions::IsValid(std::string* why) const {
  if (!std::isfinite(time_scale) || time_scale < 0.0) {
    if (why != nullptr) *why = "time_scale must be finite and >= 0 (0: as fast as possible)";
    return false;
  }
  if (output_lookahead_ns < 0) {
    if (why != nullptr) *why = "output_lookahead_ns must be >= 0";
    return false;
  }
  if (park_after_wall_ns <= 0) {
    if (why != nullptr) *why = "park_after_wall_ns must be > 0";
    return false;
  }
  return true;
}

VirtualTimeClock::VirtualTimeClock(const VirtualTimeClockOptions& options)
    : options_(options), core_(std::make_shared<Core>(options)) {}

VirtualTimeClock::~VirtualTimeClock() = default;

std::int64_t VirtualTimeClock::NowNs() const noexcept {
  return core_->now_ns.load(std::memory_order_acquire);
}

std::uint64_t VirtualTimeClock::OutputEpoch() const noexcept {
  return core_->epoch.load(std::memory_order_acquire);
}

void VirtualTimeClock::SleepForNs(std::int64_t duration_ns) {
  if (duration_ns <= 0) return;
  Wait(NowNs() + duration_ns, false, 0);
}

void VirtualTimeClock::WaitForOutput(std::int64_t deadline_ns, std::uint64_t seen_epoch) {
  Wait(deadline_ns, true, seen_epoch);
}

void VirtualTimeClock::NotifyOutput() {
  Core& core = *core_;
  bool woke = false;
  {
    const auto lock = core.Enter();
    const std::uint64_t epoch = core.epoch.fetch_add(1, std::memory_order_acq_rel) + 1;
    ++core.statistics.outputs;
    woke = core.WakeDue(epoch);
  }
  if (woke) core.cv.notify_all();
}

void VirtualTimeClock::Wait(std::int64_t deadline_ns, bool wake_on_output,
                            std::uint64_t seen_epoch) {
  Core& core = *core_;
  const std::thread::id id = std::this_thread::get_id();
  std::unique_lock lock = core.Enter();
  auto [it, inserted] = core.threads.try_emplace(id);
  if (inserted) {
    t_attachments.cores.push_back(core_);
    it->second.tid = gettid();
  }
  ThreadRecord& self = it->second;
  if (deadline_ns <= core.now_ns.load(std::memory_order_relaxed) ||
      (wake_on_output && core.epoch.load(std::memory_order_acquire) != seen_epoch)) {
    self.state = ThreadRecord::State::kRunning;
    self.running_since = WallClock::now();
    self.woken_by_output = false;
    return;
  }
  self.state = ThreadRecord::State::kWaiting;
  self.in_wait = true;
  self.deadline_ns = deadline_ns;
  self.wake_on_output = wake_on_output;
  self.seen_epoch = seen_epoch;
  const auto park_after = std::chrono::nanoseconds(options_.park_after_wall_ns);
  while (self.state == ThreadRecord::State::kWaiting) {
    if (!core.pacing && core.AdvanceOnce(lock)) continue;
    if (core.pacing) {
      core.cv.wait(lock);
      continue;
    }
    // Someone is running: wait for them, but not for ever (see "parked" in the header).
    auto park_at = WallClock::time_point::max();
    for (const auto& [other_id, record] : core.threads) {
      if (record.state == ThreadRecord::State::kRunning) {
        park_at = std::min(park_at, record.running_since + park_after);
      }
    }
    if (core.cv.wait_until(lock, park_at) == std::cv_status::timeout) {
      const auto wall_now = WallClock::now();
      for (auto& [other_id, record] : core.threads) {
        if (record.state != ThreadRecord::State::kRunning || record.in_wait ||
            wall_now < record.running_since + park_after)
          continue;
        if (core.entering.load(std::memory_order_acquire) == 0 && MayPark(record.tid)) {
          record.state = ThreadRecord::State::kParked;
          ++core.statistics.parks;
        } else {
          // Working, waiting for a CPU, or (any thread) queueing for this clock's lock: look
          // again after another park_after_wall_ns.
          record.running_since = wall_now;
          ++core.statistics.park_deferrals;
        }
      }
    }
  }
  self.in_wait = false;
  self.running_since = WallClock::now();
}

void VirtualTimeClock::AddParticipant(sim::SimulationParticipant* participant) {
  const auto lock = core_->Enter();
  core_->participants.push_back(participant);
}

void VirtualTimeClock::RemoveParticipant(sim::SimulationParticipant* participant) {
  const auto lock = core_->Enter();
  std::erase(core_->participants, participant);
}

void VirtualTimeClock::WithParticipantsLocked(const std::function<void()>& f) {
  const auto lock = core_->Enter();
  f();
}

void VirtualTimeClock::AttachCurrentThread() {
  const auto lock = core_->Enter();
  auto [it, inserted] = core_->threads.try_emplace(std::this_thread::get_id());
  if (inserted) {
    t_attachments.cores.push_back(core_);
    it->second.tid = gettid();
  }
  it->second.state = ThreadRecord::State::kRunning;
  it->second.running_since = WallClock::now();
  it->second.woken_by_output = false;
}

void VirtualTimeClock::DetachCurrentThread() { core_->Detach(std::this_thread::get_id()); }

VirtualTimeClockStatistics VirtualTimeClock::Statistics() const {
  std::lock_guard lock(core_->mutex);
  VirtualTimeClockStatistics s = core_->statistics;
  s.attached_threads = core_->threads.size();
  return s;
}

}  // namespace hrgbench::drivers::sim_station
