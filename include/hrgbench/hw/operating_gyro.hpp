#pragma once
// OperatingGyro: the electronics as a gyro (issue 28), the part of them a tuning step needs beside
// GyroElectronics: the compensation block p they hold in non-volatile memory, and the angle output
// they stream once Release closes the whole-angle loops (GyroConfig::whole_angle, mode
// kOperating). Concrete: GyroCanDevice (drivers/gyro_can, the Parameter and OperatingSample frames
// of hrg_gyro_v2.dbc); the simulated electronics answer the same frames.
//
// The block's values are the paper's p in the estimator's order (estimator/compensation.hpp
// CompensationVector): δ1 … δ6, ξ1 … ξ4, b̂, SI units (1/s, -, 1/s, 1/s, rad/s, rad/s, -, -, -,
// -, rad/s).
//
// Threads: the same one thread as the GyroElectronics it belongs to. Not real-time except
// ReadOperatingSamples and OperatingLoopsSinceRelease (no allocation, bounded wait, noexcept).
// Failure modes are values (GyroError); the block calls are refused (kInvalidState) while a wave
// is driven, free or operating.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <expected>
#include <optional>
#include <span>

#include "hrgbench/hw/gyro_electronics.hpp"

namespace hrgbench::hw {

inline constexpr int kCompensationValueCount = 11;
using CompensationValues = std::array<double, kCompensationValueCount>;

// What a write did: the block the electronics held before (nullopt when none was valid) and the
// generation of the block committed.
struct CompensationWrite {
  std::optional<CompensationValues> previous;
  std::uint32_t generation = 0;
};

// One sample of the operating mode: the gyro's angle output ∫Ω̂ dt and the wave's electrical angle
// modulo π, as the electronics computed them with the block they hold.
struct OperatingSample {
  std::uint64_t index = 0;  // sample number since release
  double angle_output_rad = 0.0;
  double wave_angle_rad = 0.0;  // [0, π)
};

// What the electronics' whole-angle loops held at one sample (estimator::WholeAngleSample), as
// they report it every few samples (GyroCanDevice: OperatingLoopsA/B, every 10th sample).
struct OperatingLoops {
  std::uint64_t index = 0;               // the sample it belongs to (OperatingSample::index)
  double energy_error = 0.0;             // (Ŝ − S*)/S*: the amplitude loop's error, relative
  double quadrature_ratio = 0.0;         // K̂/Ŝ: the quadrature loop's error
  double amplitude_effort_per_s = 0.0;   // g, 1/s (−δ1 of the unit when locked)
  double quadrature_effort_rad_s = 0.0;  // q, rad/s
};

// The loops' reports since the last release: the latest, how many, the worst errors and the sums
// their means and RMS come from. Each report is one sample's: on a noisy unit the worst |K̂/Ŝ| is
// the pick-off noise's extreme and g moves with it (the loops' proportional part), so a lock is
// judged on the means (the mean g is the unit's decay rate, −δ1, measured with the loops closed).
struct OperatingLoopsRecord {
  std::uint64_t reports = 0;     // complete reports received
  std::uint64_t incomplete = 0;  // reports of which only one frame arrived (dropped)
  std::optional<OperatingLoops> last;
  double max_abs_energy_error = 0.0;
  double max_abs_quadrature_ratio = 0.0;
  // Σ over the reports of each field (energy error, K̂/Ŝ, g, q) and of its square.
  std::array<double, 4> sum{}, sum_of_squares{};

  // Mean and RMS of field i (0 energy error, 1 K̂/Ŝ, 2 g, 3 q); NaN without reports.
  double Mean(std::size_t i) const noexcept {
    return reports == 0 ? std::nan("") : sum[i] / static_cast<double>(reports);
  }
  double Rms(std::size_t i) const noexcept {
    return reports == 0 ? std::nan("")
                        : std::sqrt(sum_of_squares[i] / static_cast<double>(reports));
  }
};

class OperatingGyro {
 public:
  virtual ~OperatingGyro() = default;

  // The block the electronics run with. Failure: kInvalidState, kTimeout, kRejected, kBusOff,
  // kTransport, kReadBackMismatch (a block whose layout, count or CRC is wrong: named).
  virtual std::expected<CompensationValues, GyroError> ReadParameters() = 0;
  // Writes `values` as the active block: reads the active one (the result's `previous`), stages
  // the new one, reads every staged word back and commits only when all match, then reads the
  // committed block back. kReadBackMismatch: nothing committed. A lost commit (a power loss)
  // leaves whichever block the electronics' memory then holds, and the error says which.
  virtual std::expected<CompensationWrite, GyroError> WriteParameters(
      const CompensationValues& values) = 0;
  // Makes the block held before the last commit active again; returns its generation.
  virtual std::expected<std::uint32_t, GyroError> RestorePreviousParameters() = 0;
  // Up to out.size() samples of the angle output (state kOperating), waiting at most
  // `timeout_ns`; fewer when the wait ends or the stream stops. Lost samples are counted in
  // GyroCounters (sequence gaps), never filled in.
  virtual std::size_t ReadOperatingSamples(std::span<OperatingSample> out,
                                           std::int64_t timeout_ns) noexcept = 0;
  // The loops' reports received so far in this run (since Release; empty before the first):
  // taken in by the same receive path, so as current as the last ReadOperatingSamples.
  virtual OperatingLoopsRecord OperatingLoopsSinceRelease() const noexcept = 0;
};

}  // namespace hrgbench::hw
