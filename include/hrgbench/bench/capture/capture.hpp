#pragma once
// CaptureThread: the real-time capture of one free run (issue 4, section 3). A dedicated thread
// reads samples from the gyro electronics into a preallocated batch, pushes them into a
// single-producer single-consumer ring (SampleRing) and counts; the non-real-time side (the
// sequencer / recorder) drains the ring concurrently with Drain().
//
// The loop does nothing else: no allocation, no logging, no lock, no exception, no system call
// beyond what ReadSamples and Clock::NowNs make (tests/unit/bench_capture/
// capture_allocation_test.cpp proves the allocation part with a counting operator new). Every
// function it calls is noexcept.
//
// Use for one run (the electronics are owned by ONE thread at a time, hw/gyro_electronics.hpp):
//   sequencer thread:  Configure → Excite → WaitReady → t0 = Release()
//                      capture.Start(electronics, ring, run)      // capture thread owns them now
//                      while (capture.Running()) { Drain(ring, samples); ... progress line ... }
//                      CaptureResult result = capture.Join();      // ownership back
//                      Drain(ring, samples); electronics.Stop(); record result
// Samples that arrive between Release and Start wait in the driver's own buffer (GyroCanDevice:
// 4096 samples = 4 s at 1 kHz) and are not lost.
//
// Units: times in ns on `run.clock` (the transport's time base; SteadyClock by default). Sample
// seq as the electronics count it: 0 = the release instant.
//
// Stop conditions, checked before every read, first one wins (CaptureTermination):
//   - count: the run is samples seq first_seq … first_seq + sample_count − 1; the capture ends as
//     soon as the last of them (or, if it was lost, a later one) has been read. Samples past the
//     end are not pushed (counted in samples_after_end).
//   - deadline: run.clock.NowNs() ≥ deadline_ns. A read never waits past the deadline.
//   - stop requested: RequestStop() (any thread) or *run.external_stop (e.g. set by a SIGINT
//     handler: std::atomic<bool> is lock-free, so setting it is async-signal-safe). Latency: at
//     most one read_timeout_ns.
//   - the electronics: kNotRunning (stream ended and nothing buffered), kBusOff, kError; and
//     kStalled when no sample has arrived for max_silence_ns.
//
// Threads: Start, Join, Running, Progress, RequestStop and the destructor are called from the
// controlling (non-real-time) thread; RequestStop and Progress also from any other thread.
// Failure modes: Start returns CaptureError (invalid run, already running, thread not created);
// everything during the run is a count or a termination value in CaptureResult.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <expected>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "hrgbench/bench/capture/realtime_setup.hpp"
#include "hrgbench/bench/capture/spsc_ring.hpp"
#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench {

using SampleRing = SpscRing<hw::GyroSample>;

// A captured sample as the run's record stores it. t_s counts from the stamp Release() returned;
// both are on the transport's time base and the driver stamps sample k at that stamp + k/fs in
// integer ns, so t_s is k/fs whatever the stamp was: `hrg-bench replay` rebuilds it bit for bit
// from a log whose stamps have another origin.
inline GyroSampleRecord ToSampleRecord(const hw::GyroSample& sample, std::int64_t release_t_ns) {
  GyroSampleRecord record;
  record.seq = sample.seq;
  record.t_s = static_cast<double>(sample.t_ns - release_t_ns) * 1e-9;
  std::copy(std::begin(sample.y), std::end(sample.y), std::begin(record.y));
  record.temperature_c = sample.temperature_c;
  record.resonant_frequency_hz = sample.resonant_frequency_hz;
  return record;
}

struct CaptureRun {
  // Count stop: capture seq first_seq … first_seq + sample_count − 1 (round(T·fs) samples of a
  // run, estimator/run_data.hpp). 0 = no count stop (then deadline_ns is required).
  std::uint64_t sample_count = 0;
  std::uint32_t first_seq = 0;  // 0: the sample at the release instant is the run's first
  // Deadline on `clock`, absolute ns; 0 = none. The sequencer sets run length + a margin, so a
  // stream that stops without a state change still ends the run.
  std::int64_t deadline_ns = 0;
  // The time base for deadline_ns and max_silence_ns; not owned, must outlive the run. nullptr:
  // a SteadyClock inside CaptureThread.
  hw::Clock* clock = nullptr;
  // Longest single ReadSamples wait: bounds the reaction time to RequestStop. 10 ms is 10 samples
  // at 1 kHz, well below the driver's buffer, and costs ~100 wake-ups/s when the stream is idle.
  std::int64_t read_timeout_ns = 10'000'000;
  // End with kStalled when no sample has arrived for this long; 0 = never (deadline only).
  std::int64_t max_silence_ns = 0;
  // Stop flag owned by the caller (e.g. the Ctrl-C handler's); nullptr = none. Only read.
  const std::atomic<bool>* external_stop = nullptr;
  RealtimeOptions realtime;

  // False, with the reason in *why, when no stop condition is set or a value is out of range.
  bool IsValid(std::string* why) const;
};

enum class CaptureTermination : std::uint8_t {
  kNotStarted,        // sentinel: Join() without a successful Start()
  kCountReached,      // the run's last sample was read
  kDeadline,          // deadline_ns passed first
  kStopRequested,     // RequestStop() or *external_stop (operator, Ctrl-C, sequencer fault)
  kDeviceNotRunning,  // ReadSamples: kNotRunning (the electronics left free run)
  kBusOff,            // ReadSamples: kBusOff
  kDeviceError,       // ReadSamples: kError (transport failure)
  kStalled,           // no sample for max_silence_ns
};

std::string_view ToString(CaptureTermination termination) noexcept;

struct CaptureResult {
  CaptureTermination termination = CaptureTermination::kNotStarted;

  std::uint64_t samples_read = 0;          // delivered by ReadSamples (all of them)
  std::uint64_t samples_pushed = 0;        // accepted by the ring: what the consumer gets
  std::uint64_t ring_overruns = 0;         // refused by a full ring: lost (the consumer sees a gap)
  std::uint64_t samples_after_end = 0;     // seq past the run's end: not pushed
  std::uint64_t sequence_regressions = 0;  // seq not after the previous one: not pushed
  std::uint64_t sequence_gaps = 0;         // seq jumps seen by the capture (events) ...
  std::uint64_t samples_missing = 0;       // ... and the samples missing in them (incl. before the
                                           // first sample read, counted from first_seq)
  std::uint64_t reads = 0;                 // ReadSamples calls
  std::uint64_t read_timeouts = 0;         // of which returned kTimeout
  std::size_t max_batch = 0;               // most samples one ReadSamples returned (lag indicator)
  std::size_t ring_high_water = 0;         // most samples queued in the ring after a push
  // Samples pushed that the driver turned back by the reference phase the electronics reported
  // (hw::GyroSample::reference_phase_rad finite): all of them with electronics that report it.
  std::uint64_t samples_reference_phase_undone = 0;

  bool any_sample = false;      // first/last below are valid
  std::uint32_t first_seq = 0;  // of the first / last sample pushed
  std::uint32_t last_seq = 0;
  std::int64_t first_t_ns = 0;
  std::int64_t last_t_ns = 0;
  std::int64_t started_ns = 0;  // run.clock at loop entry / exit
  std::int64_t ended_ns = 0;

  // Device counters (cumulative, hw::GyroCounters) at loop entry and exit; CounterDelta() is what
  // happened during this run: kernel drops, bad frames, the driver's own gap count, ...
  hw::GyroCounters counters_at_start;
  hw::GyroCounters counters_at_end;
  hw::GyroCounters CounterDelta() const noexcept;

  RealtimeReport realtime;

  // One paragraph for logs and the session record.
  std::string Report() const;
};

struct CaptureError {
  enum class Code : std::uint8_t { kInvalidArgument, kAlreadyRunning, kThreadStart };
  Code code = Code::kInvalidArgument;
  std::string message;
};

// Live numbers for the progress line; each exact, the set not taken atomically.
struct CaptureProgress {
  std::uint64_t samples_pushed = 0;
  std::uint64_t ring_overruns = 0;
  std::uint64_t samples_missing = 0;
};

class CaptureThread {
 public:
  // Allocates the read batch (`batch_capacity` samples, reused by every run). 64 samples = 64 ms
  // at 1 kHz: one read drains what a scheduling hiccup piled up, and a batch is one ring push.
  explicit CaptureThread(std::size_t batch_capacity = 64);
  // Requests a stop and joins a running capture.
  ~CaptureThread();
  CaptureThread(const CaptureThread&) = delete;
  CaptureThread& operator=(const CaptureThread&) = delete;

  // Starts the capture thread for one run. `electronics` (released, in free run) and `ring` (the
  // consumer drains it) are not owned; they must outlive Join(), and nobody else may use the
  // electronics' non-thread-safe methods or the ring's producer side until then. If
  // run.realtime.lock_memory, locks the process's memory here first (LockProcessMemory). Returns
  // once the thread has applied its real-time setup, with the report of what it got; the run
  // goes on whatever was refused. Not real-time safe (creates a thread).
  std::expected<RealtimeReport, CaptureError> Start(hw::GyroElectronics& electronics,
                                                    SampleRing& ring, const CaptureRun& run);

  // Asks the loop to end (kStopRequested). Any thread; lock-free; noexcept.
  void RequestStop() noexcept { stop_requested_.store(true, std::memory_order_relaxed); }
  // True from Start until the loop has ended (Join still needed).
  bool Running() const noexcept { return running_.load(std::memory_order_acquire); }
  CaptureProgress Progress() const noexcept;

  // Waits for the loop to end and returns its result. Without a started run: a result with
  // termination kNotStarted.
  CaptureResult Join();

 private:
  void ThreadMain() noexcept;
  CaptureTermination Loop() noexcept;
  // Checks seq order and the run's end, compacts the batch to the samples to push, returns how
  // many; true in *end_reached when the run's last sample was among them.
  std::size_t FilterBatch(std::size_t count, bool* end_reached) noexcept;

  std::vector<hw::GyroSample> batch_;
  hw::SteadyClock steady_clock_;

  // Set by Start before the thread exists, read by the thread (thread start orders them).
  hw::GyroElectronics* electronics_ = nullptr;
  SampleRing* ring_ = nullptr;
  CaptureRun run_;
  hw::Clock* clock_ = nullptr;
  // Written by the thread, read after join (join orders them).
  CaptureResult result_;
  std::uint64_t next_seq_ = 0;  // 64-bit: first_seq + sample_count may exceed 2^32
  std::uint64_t end_seq_ = 0;   // one past the run's last seq; 0 with no count stop

  std::thread thread_;
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> running_{false};
  std::atomic<bool> setup_done_{false};
  std::atomic<std::uint64_t> progress_pushed_{0};
  std::atomic<std::uint64_t> progress_overruns_{0};
  std::atomic<std::uint64_t> progress_missing_{0};
};

// Consumer side (the non-real-time thread that owns the ring's consumer end): appends every
// sample queued now to `out` and returns how many. Allocates (grows `out`) — never call it from
// the capture thread. One pass: samples pushed meanwhile wait for the next call.
std::size_t Drain(SampleRing& ring, std::vector<hw::GyroSample>& out);

}  // namespace hrgbench::bench
