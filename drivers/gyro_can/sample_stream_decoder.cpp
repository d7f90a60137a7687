#include "gyro_can/sample_stream_decoder.hpp"

#include <algorithm>
#include <cmath>

namespace hrgbench::drivers::gyro_can {

SampleStreamDecoder::SampleStreamDecoder(std::size_t capacity)
    : ring_(capacity == 0 ? 1 : capacity) {}

void SampleStreamDecoder::Start(FrameFormat format, std::uint32_t sample_rate_hz) noexcept {
  format_ = format;
  sample_rate_hz_ = sample_rate_hz == 0 ? 1 : sample_rate_hz;
  head_ = 0;
  size_ = 0;
  t0_known_ = false;
  t0_ns_ = 0;
  next_frame_ = 0;
  next_sample_ = 0;
  numbering_lost_ = false;
  pending_ = {};
  reports_seen_ = 0;
  newest_sample_ = 0;
}

void SampleStreamDecoder::SetReleaseTime(std::int64_t t0_ns) noexcept {
  t0_ns_ = t0_ns;
  t0_known_ = true;
}

SampleStreamDecoder::Placement SampleStreamDecoder::Place(
    std::uint64_t expected, std::uint64_t wire_value, std::uint64_t modulo, std::uint64_t scale,
    std::uint64_t offset, std::int64_t stamp_ns, std::uint64_t* index) const noexcept {
  const std::uint64_t delta = (wire_value + modulo - expected % modulo) % modulo;
  *index = expected + delta;
  if (!t0_known_) return Placement::kPlaced;
  // The stamp bounds the index from above only: the electronics cannot send sample k before
  // t0 + k/fs, but they may send it any time later (a starved sender catches up in a burst whose
  // frames all carry late stamps). So the stamp can refuse an index from the future, and can say
  // that a whole wrap may be missing, but never which: a guess here would shift every later
  // sample by a wrap (0.5 s at 500 Hz) and pair the halves of different samples. The tolerance (a
  // quarter of a wrap) covers t0's own lateness and the electronics' crystal against the host's
  // clock (64 samples of the 8-bit counter: 100 ppm over 640 000 samples).
  // In unsigned arithmetic: any two stamps (a fuzzed frame's too) differ by less than 2^64, which
  // the signed difference cannot always hold (the full sanitized run's finding).
  const double elapsed_s = stamp_ns > t0_ns_
                               ? static_cast<double>(static_cast<std::uint64_t>(stamp_ns) -
                                                     static_cast<std::uint64_t>(t0_ns_)) *
                                     1e-9
                               : 0.0;
  const double bound =
      elapsed_s * static_cast<double>(sample_rate_hz_) * static_cast<double>(scale) +
      static_cast<double>(offset) + static_cast<double>(modulo / 4);
  if (static_cast<double>(*index) > bound) return Placement::kStale;
  if (static_cast<double>(*index + modulo) <= bound) return Placement::kAmbiguous;
  return Placement::kPlaced;
}

void SampleStreamDecoder::LoseNumbering() noexcept {
  if (!numbering_lost_) ++counters_.sequence_gaps;
  numbering_lost_ = true;
  pending_.valid = false;
}

void SampleStreamDecoder::OnSampleHalf(const SampleHalf& half, std::int64_t stamp_ns) noexcept {
  if (numbering_lost_) {
    if (half.half == 1) ++counters_.samples_lost;
    return;
  }
  std::uint64_t frame = 0;
  switch (Place(next_frame_, 2u * half.seq + half.half, 2u * kClassicSeqModulo, 2, half.half,
                stamp_ns, &frame)) {
    case Placement::kPlaced:
      break;
    case Placement::kStale:  // a frame CAN delivered twice, or one from before a loss
      ++counters_.sequence_gaps;
      return;
    case Placement::kAmbiguous:  // at least the samples the counter says are missing are lost
      LoseNumbering();
      counters_.samples_lost += frame / 2 - std::min(frame / 2, next_sample_) + half.half;
      return;
  }
  if (frame != next_frame_) ++counters_.sequence_gaps;
  next_frame_ = frame + 1;
  const std::uint64_t sample = frame / 2;
  if (half.half == 0) {
    pending_ = {sample, half.y_raw[0], half.y_raw[1], true};
    return;
  }
  if (pending_.valid && pending_.sample == sample) {
    const std::int32_t y[4] = {pending_.y1, pending_.y2, half.y_raw[0], half.y_raw[1]};
    Emit(sample, y);
  } else if (sample >= next_sample_) {  // a second half without its first: that sample is lost
    counters_.samples_lost += sample + 1 - next_sample_;
    next_sample_ = sample + 1;
  }
  pending_.valid = false;
}

void SampleStreamDecoder::OnSampleFd(const SampleFdBlock& block, std::int64_t stamp_ns) noexcept {
  if (numbering_lost_) {
    counters_.samples_lost += block.count;
    return;
  }
  std::uint64_t first = 0;
  switch (Place(next_frame_, block.seq, kFdSeqModulo, 1, 0, stamp_ns, &first)) {
    case Placement::kPlaced:
      break;
    case Placement::kStale:
      ++counters_.sequence_gaps;
      return;
    case Placement::kAmbiguous:
      LoseNumbering();
      counters_.samples_lost += first - std::min(first, next_sample_) + block.count;
      return;
  }
  if (first != next_frame_) ++counters_.sequence_gaps;
  next_frame_ = first + block.count;
  for (std::size_t s = 0; s < block.count && s < kSamplesPerFdFrame; ++s) {
    const auto& raw = block.y_raw[s];
    const std::int32_t y[4] = {raw[0], raw[1], raw[2], raw[3]};
    Emit(first + s, y);
  }
}

void SampleStreamDecoder::OnReferencePhase(const ReferencePhaseReport& report,
                                           std::int64_t stamp_ns) noexcept {
  // A report precedes its sample's frames: its number is at or after the next sample expected.
  // One that cannot be placed is dropped (the samples around it bridge to the next report).
  std::uint64_t sample = 0;
  if (numbering_lost_ || Place(next_sample_, report.seq, kFdSeqModulo, 1, 0, stamp_ns, &sample) !=
                             Placement::kPlaced) {
    return;
  }
  if (reports_seen_ > 0 && sample <= reports_[1].sample) return;  // stale or repeated
  reports_[0] = reports_[1];
  reports_[1] = {sample, DequantiseReferencePhase(report.phase_raw)};
  if (reports_seen_ < 2) ++reports_seen_;
  if (reports_seen_ == 1) reports_[0] = reports_[1];  // before the first: χ as at the first
  // The samples already in the ring between the two reports can now be turned.
  for (std::size_t i = size_; i-- > 0;) {
    hw::GyroSample& slot = ring_[(head_ + i) % ring_.size()];
    if (slot.seq < reports_[0].sample) break;
    if (std::isnan(slot.reference_phase_rad))
      slot.reference_phase_rad = InterpolatedPhase(slot.seq);
  }
}

double SampleStreamDecoder::InterpolatedPhase(std::uint64_t sample) const noexcept {
  if (reports_seen_ == 0 || sample > reports_[1].sample) return std::nan("");
  const Report& a = reports_[0];
  const Report& b = reports_[1];
  if (sample <= a.sample || b.sample == a.sample)
    return sample == b.sample ? b.phase_rad : a.phase_rad;
  constexpr double kTwoPi = 4294967296.0 * kReferencePhaseLsbRad;
  // The shorter way round: χ moves by ≪ π between reports.
  const double step = std::remainder(b.phase_rad - a.phase_rad, kTwoPi);
  const double fraction =
      static_cast<double>(sample - a.sample) / static_cast<double>(b.sample - a.sample);
  return a.phase_rad + fraction * step;
}

void SampleStreamDecoder::OnStatus(double temperature_c, double resonant_frequency_hz) noexcept {
  temperature_c_ = temperature_c;
  resonant_frequency_hz_ = resonant_frequency_hz;
}

void SampleStreamDecoder::Emit(std::uint64_t sample, const std::int32_t (&y_raw)[4]) noexcept {
  if (sample < next_sample_) return;  // cannot happen with monotonic unwrapping; be safe
  counters_.samples_lost += sample - next_sample_;
  next_sample_ = sample + 1;
  if (size_ == ring_.size()) {
    ++counters_.buffer_overruns;
    return;
  }
  hw::GyroSample& slot = ring_[(head_ + size_) % ring_.size()];
  slot.seq = static_cast<std::uint32_t>(sample);
  for (int c = 0; c < 4; ++c) slot.y[c] = DequantiseY(y_raw[c]);
  slot.reference_phase_rad = InterpolatedPhase(sample);
  slot.temperature_c = temperature_c_;
  slot.resonant_frequency_hz = resonant_frequency_hz_;
  newest_sample_ = sample;
  ++size_;
  ++counters_.samples_decoded;
}

std::size_t SampleStreamDecoder::Pop(std::span<hw::GyroSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && size_ > 0) {
    hw::GyroSample sample = ring_[head_];
    if (std::isnan(sample.reference_phase_rad)) {
      // Before the run's first report: as received. After it: wait for the report after it.
      if (reports_seen_ > 0 && sample.seq > reports_[0].sample) {
        if (newest_sample_ - sample.seq < kReferenceHoldSamples) break;
        ++counters_.reference_phases_missing;
      }
    } else {
      const double c = std::cos(sample.reference_phase_rad);
      const double s = std::sin(sample.reference_phase_rad);
      for (int channel = 0; channel < 2; ++channel) {
        const double re = sample.y[2 * channel], im = sample.y[2 * channel + 1];
        sample.y[2 * channel] = c * re - s * im;
        sample.y[2 * channel + 1] = s * re + c * im;
      }
    }
    // Integer ns: exact for any seq (seq·1e9 < 2^63 for seq < 2^32).
    sample.t_ns = t0_ns_ + static_cast<std::int64_t>(static_cast<std::uint64_t>(sample.seq) *
                                                     1'000'000'000ull / sample_rate_hz_);
    out[n++] = sample;
    head_ = (head_ + 1) % ring_.size();
    --size_;
  }
  return n;
}

}  // namespace hrgbench::drivers::gyro_can
