#include "hrgbench/analysis/run_acceptance.hpp"

#include <cmath>
#include <cstdio>

namespace hrgbench::bench {
namespace {

std::string Format(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace

double RelativeChange(double start, double end) noexcept {
  if (!std::isfinite(start) || !std::isfinite(end) || start == 0.0) return 0.0;
  return std::abs(end - start) / std::abs(start);
}

std::optional<std::string> TooManyDrops(int run_id, std::uint64_t sequence_gaps,
                                        std::uint64_t samples_lost,
                                        const CaptureCriteria& capture) {
  if (static_cast<std::int64_t>(sequence_gaps) <= capture.max_sequence_gaps &&
      static_cast<std::int64_t>(samples_lost) <= capture.max_samples_lost)
    return std::nullopt;
  return "too many drops in run " + std::to_string(run_id) + ": " + std::to_string(sequence_gaps) +
         " gaps, " + std::to_string(samples_lost) + " samples lost (allowed " +
         std::to_string(capture.max_sequence_gaps) + ", " +
         std::to_string(capture.max_samples_lost) + ")";
}

RunDriftJudgement JudgeRunDrift(double temperature_start_c, double temperature_end_c,
                                double frequency_start_hz, double frequency_end_hz,
                                const DriftCriteria& criteria) {
  const double temperature_change = RelativeChange(temperature_start_c, temperature_end_c);
  const double frequency_change = RelativeChange(frequency_start_hz, frequency_end_hz);
  RunDriftJudgement judgement;
  if (temperature_change > criteria.max_temperature_change_rel)
    judgement.what = "temperature changed by " + Format("%.3g %%", 100 * temperature_change);
  if (criteria.max_frequency_change_rel && frequency_change > *criteria.max_frequency_change_rel)
    judgement.what +=
        (judgement.what.empty() ? "" : ", ") +
        ("resonant frequency changed by " + Format("%.3g %%", 100 * frequency_change));
  if (!judgement.what.empty())
    judgement.drift =
        criteria.action == DriftAction::kReject ? RunDrift::kRejected : RunDrift::kFlagged;
  return judgement;
}

}  // namespace hrgbench::bench
