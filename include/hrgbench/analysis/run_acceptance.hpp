#pragma once
// Whether a captured run is accepted into the record as complete: what the sequencer decides about
// a run once its capture ended (the hardware's part, settling, excitation and the capture itself,
// stays in the sequencer). Pure functions of their inputs; thread-safe; allocate (not for the
// capture path: called once per run after it).
//
//   drops   more sequence gaps or lost samples than [capture] allows: the bench's fault, the run
//           aborted and the unit's session an ERROR (STYLE rule 9: it says nothing about the unit)
//   drift   a temperature or resonant-frequency change beyond [drift] (the paper estimates only
//           when temperature is stationary, change < 1 %): the run is flagged (kept for the
//           estimator, marked in the record) or rejected (not given to the estimator), as [drift]
//           action says

#include <cstdint>
#include <optional>
#include <string>

#include "hrgbench/config/sequence_config.hpp"

namespace hrgbench::bench {

// |end − start| / |start|; 0 when either is not finite or start is 0 (nothing to compare).
double RelativeChange(double start, double end) noexcept;

// The reason the run is refused for its drops ("too many drops in run 3: 2 gaps, 17 samples lost
// (allowed 0, 0)"), or none when they are within `capture`. `samples_lost`: missing in gaps plus
// refused by a full ring.
std::optional<std::string> TooManyDrops(int run_id, std::uint64_t sequence_gaps,
                                        std::uint64_t samples_lost, const CaptureCriteria& capture);

enum class RunDrift { kSteady, kFlagged, kRejected };

struct RunDriftJudgement {
  RunDrift drift = RunDrift::kSteady;
  // What moved: "temperature changed by 1.5 %", "resonant frequency changed by 0.2 %", or both
  // joined by ", "; empty when steady.
  std::string what;
};

// Temperatures in °C (as the paper states its criterion), frequencies in Hz; NaN where the
// electronics reported none (then that change is not judged).
RunDriftJudgement JudgeRunDrift(double temperature_start_c, double temperature_end_c,
                                double frequency_start_hz, double frequency_end_hz,
                                const DriftCriteria& criteria);

}  // namespace hrgbench::bench
