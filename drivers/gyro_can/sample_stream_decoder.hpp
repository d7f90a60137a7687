#pragma once
// SampleStreamDecoder: turns the decoded sample frames of one free run (classic halves or FD
// blocks, see README.md "Sequence counter") into whole GyroSamples in a ring allocated once, and
// accounts for every frame that is missing. Pure logic: no bus, no clock (receive stamps are
// passed in), so it is unit-testable on its own.
//
// Reference phase (README "Reference phase", frame ReferencePhase): electronics that report their
// reference's phase χ send it for every kReferencePhaseInterval-th sample, before that sample's
// frames. Once a report arrived in a run, each sample gets χ linearly interpolated between the two
// reports around it (the shorter way round 2π) and its channels are turned back by it, (y1 + i·y2)
// and (y3 + i·y4) times e^{+iχ} (estimator/reference_phase.hpp's convention), so y is what a
// reference kept at its lock-at-release frequency would have given; GyroSample::reference_phase_rad
// says by how much. A sample waits in the ring for the report after it; when that report does not
// come within kReferenceHoldSamples samples, the sample is delivered as received (χ NaN) and
// counted in reference_phases_missing. Samples before the run's first report (electronics that
// never report: all of them) are delivered as received, χ NaN.
//
// Threads: one thread (the capture thread). Real-time safety: every method except the constructor
// is noexcept and allocation-free.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "gyro_can/gyro_codec.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"

namespace hrgbench::drivers::gyro_can {

struct SampleStreamCounters {
  std::uint64_t samples_decoded = 0;           // whole samples put into the ring
  std::uint64_t sequence_gaps = 0;             // breaks in the frame sequence (events)
  std::uint64_t samples_lost = 0;              // sample numbers skipped (incomplete or never seen)
  std::uint64_t buffer_overruns = 0;           // whole samples discarded because the ring was full
  std::uint64_t reference_phases_missing = 0;  // samples delivered unturned: no report after them
};

class SampleStreamDecoder {
 public:
  // Allocates the ring (`capacity` samples, ≥ 1).
  explicit SampleStreamDecoder(std::size_t capacity);

  // Starts a run: empties the ring and resets the sequence to sample 0. The release time is
  // unknown until SetReleaseTime (samples may arrive before the release Ack when it was lost).
  void Start(FrameFormat format, std::uint32_t sample_rate_hz) noexcept;
  // t0 of the run (ns, receive time base); enables unwrapping the 8-bit seq against time.
  void SetReleaseTime(std::int64_t t0_ns) noexcept;

  void OnSampleHalf(const SampleHalf& half, std::int64_t stamp_ns) noexcept;
  void OnSampleFd(const SampleFdBlock& block, std::int64_t stamp_ns) noexcept;
  void OnReferencePhase(const ReferencePhaseReport& report, std::int64_t stamp_ns) noexcept;
  // The electronics' latest status report: every sample completed from now on carries its
  // temperature and frequency (GyroSample). Kept across Start(): a run's first samples carry the
  // report that preceded its release.
  void OnStatus(double temperature_c, double resonant_frequency_hz) noexcept;

  // Samples a sample waits for the report after it (a lost report or two are bridged).
  static constexpr std::uint64_t kReferenceHoldSamples = 4 * kReferencePhaseInterval;

  // Moves up to out.size() samples out of the ring, oldest first, stamping each with
  // t0 + seq·1e9/fs (and turning it back by its reference phase, above). Returns how many.
  std::size_t Pop(std::span<hw::GyroSample> out) noexcept;
  std::size_t Buffered() const noexcept { return size_; }  // including samples waiting for χ
  const SampleStreamCounters& counters() const noexcept { return counters_; }

 private:
  struct Pending {
    std::uint64_t sample = 0;
    std::int32_t y1 = 0;
    std::int32_t y2 = 0;
    bool valid = false;
  };
  // Where a wrapped counter value lies: the first index at or after `expected` with that value
  // (kPlaced), unless the receive stamp says otherwise (t0 known): an index the sender cannot have
  // produced yet by that stamp is a repeated or stale frame (kStale), and a stamp late enough to
  // leave room for a whole further wrap of the counter makes the index unknowable (kAmbiguous: a
  // sender that fell behind and a loss of a whole wrap look the same; see README "Sequence
  // counter"). `scale` converts samples to counter units, `offset` is the frame's place within
  // its sample.
  enum class Placement { kPlaced, kStale, kAmbiguous };
  Placement Place(std::uint64_t expected, std::uint64_t wire_value, std::uint64_t modulo,
                  std::uint64_t scale, std::uint64_t offset, std::int64_t stamp_ns,
                  std::uint64_t* index) const noexcept;
  // The run's sample numbers cannot be known any more (an ambiguous gap): every later sample frame
  // of the run is refused and counted lost, never delivered with a guessed number.
  void LoseNumbering() noexcept;
  void Emit(std::uint64_t sample, const std::int32_t (&y_raw)[4]) noexcept;
  // χ at `sample` from the last two reports, NaN when the sample is not between them.
  double InterpolatedPhase(std::uint64_t sample) const noexcept;
  struct Report {
    std::uint64_t sample = 0;
    double phase_rad = 0.0;  // in [0, 2π)
  };

  std::vector<hw::GyroSample> ring_;
  std::size_t head_ = 0;  // oldest
  std::size_t size_ = 0;
  FrameFormat format_ = FrameFormat::kClassic;
  std::uint32_t sample_rate_hz_ = 1000;
  std::int64_t t0_ns_ = 0;
  bool t0_known_ = false;
  std::uint64_t next_frame_ = 0;   // classic: expected 2·sample + half; FD: expected sample
  std::uint64_t next_sample_ = 0;  // next sample number not yet delivered or counted lost
  bool numbering_lost_ = false;    // LoseNumbering() was called in this run
  Pending pending_;
  // The last two reference-phase reports of the run (reports_seen_ of them, 0, 1 or 2) and the
  // newest sample number received.
  Report reports_[2];
  int reports_seen_ = 0;
  std::uint64_t newest_sample_ = 0;
  double temperature_c_ = std::numeric_limits<double>::quiet_NaN();
  double resonant_frequency_hz_ = std::numeric_limits<double>::quiet_NaN();
  SampleStreamCounters counters_;
};

}  // namespace hrgbench::drivers::gyro_can
