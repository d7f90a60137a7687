#include <algorithm>
#include <cmath>
#include <span>
#include <system_error>

#include "hrgbench/bench/capture/capture.hpp"

namespace hrgbench::bench {

CaptureThread::CaptureThread(std::size_t batch_capacity)
    : batch_(std::max<std::size_t>(batch_capacity, 1)) {}

CaptureThread::~CaptureThread() {
  if (thread_.joinable()) {
    RequestStop();
    thread_.join();
  }
}

std::expected<RealtimeReport, CaptureError> CaptureThread::Start(hw::GyroElectronics& electronics,
                                                                 SampleRing& ring,
                                                                 const CaptureRun& run) {
  if (thread_.joinable()) {
    return std::unexpected(
        CaptureError{CaptureError::Code::kAlreadyRunning, "a capture is running: Join() it first"});
  }
  std::string why;
  if (!run.IsValid(&why)) {
    return std::unexpected(CaptureError{CaptureError::Code::kInvalidArgument, why});
  }
  electronics_ = &electronics;
  ring_ = &ring;
  run_ = run;
  clock_ = run.clock != nullptr ? run.clock : &steady_clock_;
  result_ = CaptureResult{};
  next_seq_ = run.first_seq;
  end_seq_ = run.sample_count > 0 ? run.first_seq + run.sample_count : 0;
  stop_requested_.store(false, std::memory_order_relaxed);
  progress_pushed_.store(0, std::memory_order_relaxed);
  progress_overruns_.store(0, std::memory_order_relaxed);
  progress_missing_.store(0, std::memory_order_relaxed);
  setup_done_.store(false, std::memory_order_relaxed);

  // mlockall before the thread exists: its stack and everything the loop touches is then mapped
  // and locked, and the process-wide call is made from a thread where its cost does not matter.
  if (run.realtime.lock_memory) result_.realtime.memory_lock = LockProcessMemory();

  // The batch is written once here, in the controlling thread, so its pages are resident.
  std::fill(batch_.begin(), batch_.end(), hw::GyroSample{});

  running_.store(true, std::memory_order_release);
  try {
    thread_ = std::thread([this]() noexcept { ThreadMain(); });
  } catch (const std::system_error& e) {
    running_.store(false, std::memory_order_release);
    return std::unexpected(CaptureError{CaptureError::Code::kThreadStart,
                                        std::string("capture thread not created: ") + e.what()});
  }
  // Bounded: the thread's setup is a few system calls and touching its stack.
  setup_done_.wait(false, std::memory_order_acquire);
  return result_.realtime;  // written by the thread before setup_done_ (release/acquire)
}

CaptureProgress CaptureThread::Progress() const noexcept {
  return {progress_pushed_.load(std::memory_order_relaxed),
          progress_overruns_.load(std::memory_order_relaxed),
          progress_missing_.load(std::memory_order_relaxed)};
}

CaptureResult CaptureThread::Join() {
  if (!thread_.joinable()) return CaptureResult{};
  thread_.join();
  return result_;
}

void CaptureThread::ThreadMain() noexcept {
  // Setup (may allocate: the report's strings). Not part of the real-time loop.
  try {
    // Before Start() returns: a simulated clock must not run on while this thread starts.
    clock_->AttachCurrentThread();
    realtime_internal::ApplyToCallingThread(run_.realtime, result_.realtime);
  } catch (...) {
    // Only std::bad_alloc from a reason string: the setup calls themselves were made; carry on
    // with a report that says it is incomplete (applied stays false).
  }
  setup_done_.store(true, std::memory_order_release);
  setup_done_.notify_one();

  result_.termination = Loop();
  // Running() turns false before this thread lets a simulated clock go: the other way round, the
  // sequencer, still seeing Running(), would sleep through seconds of virtual time in that gap.
  running_.store(false, std::memory_order_release);
  try {
    clock_->DetachCurrentThread();
  } catch (...) {
    // Only a simulated clock's bookkeeping can fail here; the capture is over either way.
  }
}

CaptureTermination CaptureThread::Loop() noexcept {
  CaptureResult& r = result_;
  hw::GyroElectronics& electronics = *electronics_;
  SampleRing& ring = *ring_;
  const hw::Clock& clock = *clock_;
  const std::span<hw::GyroSample> batch(batch_);

  r.counters_at_start = electronics.Counters();
  r.started_ns = clock.NowNs();
  std::int64_t last_sample_ns = r.started_ns;
  CaptureTermination termination = CaptureTermination::kStopRequested;

  for (;;) {
    if (stop_requested_.load(std::memory_order_relaxed) ||
        (run_.external_stop != nullptr && run_.external_stop->load(std::memory_order_relaxed))) {
      termination = CaptureTermination::kStopRequested;
      break;
    }
    const std::int64_t now_ns = clock.NowNs();
    std::int64_t timeout_ns = run_.read_timeout_ns;
    if (run_.deadline_ns != 0) {
      if (now_ns >= run_.deadline_ns) {
        termination = CaptureTermination::kDeadline;
        break;
      }
      timeout_ns = std::min(timeout_ns, run_.deadline_ns - now_ns);
    }

    const hw::GyroReadResult read = electronics.ReadSamples(batch, timeout_ns);
    ++r.reads;
    if (read.status == hw::GyroReadStatus::kOk) {
      const std::size_t count = std::min(read.count, batch.size());
      r.samples_read += count;
      r.max_batch = std::max(r.max_batch, count);
      bool end_reached = false;
      const std::size_t keep = FilterBatch(count, &end_reached);
      const std::size_t pushed = ring.Push(std::span<const hw::GyroSample>(batch.first(keep)));
      r.samples_pushed += pushed;
      r.ring_overruns += keep - pushed;
      for (std::size_t i = 0; i < pushed; ++i) {
        if (!std::isnan(batch[i].reference_phase_rad)) ++r.samples_reference_phase_undone;
      }
      if (pushed > 0) {
        if (!r.any_sample) {
          r.any_sample = true;
          r.first_seq = batch[0].seq;
          r.first_t_ns = batch[0].t_ns;
        }
        r.last_seq = batch[pushed - 1].seq;
        r.last_t_ns = batch[pushed - 1].t_ns;
      }
      r.ring_high_water = std::max(r.ring_high_water, ring.Size());
      progress_pushed_.store(r.samples_pushed, std::memory_order_relaxed);
      progress_overruns_.store(r.ring_overruns, std::memory_order_relaxed);
      progress_missing_.store(r.samples_missing, std::memory_order_relaxed);
      last_sample_ns = clock.NowNs();
      if (end_reached) {
        termination = CaptureTermination::kCountReached;
        break;
      }
      continue;
    }
    if (read.status == hw::GyroReadStatus::kTimeout) {
      ++r.read_timeouts;
      if (run_.max_silence_ns > 0 && clock.NowNs() - last_sample_ns >= run_.max_silence_ns) {
        termination = CaptureTermination::kStalled;
        break;
      }
      continue;
    }
    termination = read.status == hw::GyroReadStatus::kNotRunning
                      ? CaptureTermination::kDeviceNotRunning
                  : read.status == hw::GyroReadStatus::kBusOff ? CaptureTermination::kBusOff
                                                               : CaptureTermination::kDeviceError;
    break;
  }

  r.ended_ns = clock.NowNs();
  r.counters_at_end = electronics.Counters();
  return termination;
}

std::size_t CaptureThread::FilterBatch(std::size_t count, bool* end_reached) noexcept {
  CaptureResult& r = result_;
  std::size_t keep = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const hw::GyroSample& sample = batch_[i];
    const std::uint64_t seq = sample.seq;
    if (*end_reached || (end_seq_ != 0 && seq >= end_seq_)) {
      // A sample past the end also ends the run when the last one itself was lost.
      if (!*end_reached && seq > next_seq_) {
        ++r.sequence_gaps;
        r.samples_missing += end_seq_ - next_seq_;
      }
      *end_reached = true;
      ++r.samples_after_end;
      continue;
    }
    if (seq < next_seq_) {  // duplicate or out of order: the driver promises neither
      ++r.sequence_regressions;
      continue;
    }
    if (seq > next_seq_) {
      ++r.sequence_gaps;
      r.samples_missing += seq - next_seq_;
    }
    next_seq_ = seq + 1;
    if (keep != i) batch_[keep] = sample;
    ++keep;
    if (end_seq_ != 0 && next_seq_ >= end_seq_) *end_reached = true;
  }
  return keep;
}

}  // namespace hrgbench::bench
