#pragma once
// FakeGyroElectronics: an in-process hw::GyroElectronics already in free run, producing samples
// whose content is a function of seq (so a consumer can check every value), on a ManualClock it
// advances itself by one sample period per sample (or by the timeout on a timeout): a capture
// against it runs as fast as the CPU allows and is deterministic. Scripted faults: lost seqs
// (gaps), a stream that ends (kNotRunning), goes silent (kTimeout), bus-off or a transport error
// after a chosen number of samples.
//
// ReadSamples runs in the capture thread; on every call it records what that thread looks like
// (scheduling policy, CPU, and the value of an optional probe, e.g. the thread's allocation count),
// so tests can check the capture thread from inside.
//
// Threads: ReadSamples from the capture thread; the rest after Join (or atomics).

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <new>
#include <set>
#include <thread>

#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"

namespace hrgbench::testing {

struct FakeGyroScript {
  std::uint32_t sample_rate_hz = 1000;
  std::uint64_t total_samples = UINT64_MAX;  // seqs produced (lost ones included) before the end
  hw::GyroReadStatus end_status = hw::GyroReadStatus::kNotRunning;  // what follows the last one
  std::size_t max_per_read = SIZE_MAX;      // samples per ReadSamples at most
  std::set<std::uint32_t> lost_seqs;        // never delivered (a gap)
  std::set<std::uint32_t> duplicated_seqs;  // delivered twice (a regression)
  // On a timeout, also sleep this long in real time (tests that stop a capture from outside).
  std::int64_t real_sleep_on_timeout_ns = 0;
  // Allocate (and free) in every ReadSamples: proves an allocation probe sees the capture thread.
  bool allocate_in_read = false;
};

// y of sample `seq` (exactly representable, so equality can be tested).
inline double FakeY(std::uint32_t seq, int channel) {
  return static_cast<double>(seq) * 0.25 + static_cast<double>(channel);
}

class FakeGyroElectronics final : public hw::GyroElectronics {
 public:
  FakeGyroElectronics(hw::ManualClock& clock, FakeGyroScript script)
      : clock_(clock), script_(std::move(script)), t0_ns_(clock.NowNs()) {}

  std::expected<void, hw::GyroError> Configure(const hw::GyroConfig&) override { return {}; }
  std::expected<void, hw::GyroError> Excite(const hw::WaveState&) override { return {}; }
  std::expected<hw::GyroStatus, hw::GyroError> WaitReady(std::int64_t) override {
    return hw::GyroStatus{};
  }
  std::expected<std::int64_t, hw::GyroError> Release() override { return t0_ns_; }
  std::expected<void, hw::GyroError> Stop() override { return {}; }
  std::expected<hw::GyroStatus, hw::GyroError> RequestStatus() override { return hw::GyroStatus{}; }

  hw::GyroReadResult ReadSamples(std::span<hw::GyroSample> out,
                                 std::int64_t timeout_ns) noexcept override {
    Observe();
    ++reads_;
    if (script_.allocate_in_read) {
      std::uint64_t* volatile escaped = new (std::nothrow) std::uint64_t(1);  // not elided
      delete escaped;
    }
    const std::int64_t period_ns = 1'000'000'000 / script_.sample_rate_hz;
    if (next_seq_ >= script_.total_samples) {
      if (script_.end_status == hw::GyroReadStatus::kTimeout) {
        clock_.Advance(timeout_ns);
        if (script_.real_sleep_on_timeout_ns > 0) {
          std::this_thread::sleep_for(std::chrono::nanoseconds(script_.real_sleep_on_timeout_ns));
        }
        counters_.timeouts.fetch_add(1, std::memory_order_relaxed);
      }
      if (script_.end_status == hw::GyroReadStatus::kBusOff) state_.store(hw::GyroMode::kFaulted);
      if (script_.end_status == hw::GyroReadStatus::kNotRunning)
        state_.store(hw::GyroMode::kStopped);
      return {0, script_.end_status};
    }
    const std::size_t limit = std::min(out.size(), script_.max_per_read);
    std::size_t n = 0;
    if (pending_duplicate_ && limit > 0) {  // the copy that did not fit into the last read
      Fill(out[n++], static_cast<std::uint32_t>(next_seq_ - 1));
      pending_duplicate_ = false;
    }
    while (n < limit && next_seq_ < script_.total_samples) {
      const auto seq = static_cast<std::uint32_t>(next_seq_);
      if (script_.lost_seqs.contains(seq)) {
        counters_.sequence_gaps.fetch_add(1, std::memory_order_relaxed);
        counters_.samples_lost.fetch_add(1, std::memory_order_relaxed);
      } else {
        Fill(out[n++], seq);
        if (script_.duplicated_seqs.contains(seq)) {
          if (n < limit) {
            Fill(out[n++], seq);
          } else {
            pending_duplicate_ = true;
          }
        }
      }
      ++next_seq_;
      clock_.Advance(period_ns);
    }
    counters_.samples_decoded.fetch_add(n, std::memory_order_relaxed);
    counters_.frames_received.fetch_add(2 * n, std::memory_order_relaxed);
    if (n == 0) return ReadSamples(out, timeout_ns);  // only lost seqs this time: keep going
    return {n, hw::GyroReadStatus::kOk};
  }

  hw::GyroMode State() const noexcept override { return state_.load(); }
  hw::GyroStatus LastStatus() const noexcept override { return {}; }
  hw::GyroCounters Counters() const noexcept override {
    hw::GyroCounters c;
    c.frames_received = counters_.frames_received.load(std::memory_order_relaxed);
    c.samples_decoded = counters_.samples_decoded.load(std::memory_order_relaxed);
    c.sequence_gaps = counters_.sequence_gaps.load(std::memory_order_relaxed);
    c.samples_lost = counters_.samples_lost.load(std::memory_order_relaxed);
    c.timeouts = counters_.timeouts.load(std::memory_order_relaxed);
    return c;
  }

  // Called at the start of every ReadSamples (in the capture thread); its value is recorded.
  std::function<std::int64_t()> probe;
  std::int64_t first_probe = 0;
  std::int64_t last_probe = 0;
  int observed_policy = -1;  // sched_getscheduler(0) in the calling thread
  int observed_cpu = -1;
  std::uint64_t reads_ = 0;
  std::int64_t t0_ns() const { return t0_ns_; }

 private:
  void Fill(hw::GyroSample& sample, std::uint32_t seq) const noexcept {
    sample.seq = seq;
    sample.t_ns = t0_ns_ + static_cast<std::int64_t>(seq) * 1'000'000'000 /
                               static_cast<std::int64_t>(script_.sample_rate_hz);
    for (int k = 0; k < 4; ++k) sample.y[k] = FakeY(seq, k);
  }
  void Observe() noexcept {
    if (probe) {
      last_probe = probe();
      if (reads_ == 0) first_probe = last_probe;
    }
    if (reads_ == 0) {
      observed_policy = sched_getscheduler(0);  // 0: the calling thread (Linux: a task id)
      observed_cpu = sched_getcpu();
    }
  }

  hw::ManualClock& clock_;
  FakeGyroScript script_;
  std::int64_t t0_ns_;
  std::uint64_t next_seq_ = 0;
  bool pending_duplicate_ = false;
  std::atomic<hw::GyroMode> state_{hw::GyroMode::kFreeRun};
  struct {
    std::atomic<std::uint64_t> frames_received{0};
    std::atomic<std::uint64_t> samples_decoded{0};
    std::atomic<std::uint64_t> sequence_gaps{0};
    std::atomic<std::uint64_t> samples_lost{0};
    std::atomic<std::uint64_t> timeouts{0};
  } counters_;
};

}  // namespace hrgbench::testing
