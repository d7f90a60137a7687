#pragma once
// SequenceConfig: the run plan of a session (bench_configs/sequence-*.toml): the free runs (table
// rate Ω, wave state to excite, free-run length, sample rate) and the criteria the sequencer
// applies around them: when the table counts as settled, how long to wait for anything, when the
// gyro is warm, when a run's temperature drifted too much, how many lost samples a run may have.
// Plain data; every key, unit and default is in bench_configs/README.md, and the in-class defaults
// are the documented ones.
//
// Loading is strict (STYLE rule 10); errors name file, line, key and value. Not thread-safe; not
// for real-time use. Loaders return std::expected, never throw (except std::bad_alloc).

#include <cstddef>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/estimator/run_data.hpp"

namespace hrgbench::bench {

// The wave-state limits of the gyro protocol (hw/gyro_electronics.hpp WaveState).
inline constexpr double kMaxWaveAmplitude = 6.5535;
inline constexpr double kMaxWaveQuadrature = 3.2767;
inline constexpr double kMaxWaveAngleRad = 3.2767;
// A run of more samples is a typo in a rate or a length (same bound as the simulation specs).
inline constexpr double kMaxSamplesPerRun = 1e7;

struct SequenceRun {
  double omega_rad_s =
      0.0;                 // table rate to command (the Earth-rate part is added for the estimator)
  double a = 1.0;          // wave amplitude to excite, (0, 6.5535]
  double b = 0.0;          // quadrature, |b| < a
  double theta_rad = 0.0;  // wave angle, |θ| <= 3.2767 rad
  double free_run_s = 10.0;  // capture length after the release; n = round(free_run_s·fs) samples
  std::uint32_t sample_rate_hz = 100;  // fs, integer (the electronics' configuration is in Hz)

  // Where omega_rad_s and sample_rate_hz were written (for errors of checks against the station).
  std::size_t omega_line = 0;
  std::size_t sample_rate_line = 0;

  std::size_t Samples() const;  // round(free_run_s · sample_rate_hz)
};

// [settle]: the table is settled when |measured − commanded| <= rate_tolerance_rad_s (and the
// table's own at-rate bit is set) continuously for dwell_s (hw::StableCriteria).
struct SettleCriteria {
  double rate_tolerance_rad_s = 1e-3;
  double dwell_s = 1.0;
  double poll_period_s = 0.05;
};

// [timeouts]
struct SequenceTimeouts {
  double settle_s = 60.0;     // table to rate and settled, including the ramp
  double excite_s = 10.0;     // Excite → "ready"
  double run_margin_s = 5.0;  // a capture that has not ended after free_run_s + this is an ERROR
};

// [warmup]: before the first run, the bench waits at least min_s, then until the gyro's temperature
// drifts by no more than max_drift_c over the last window_s (or gives up after timeout_s: ERROR).
struct WarmupCriteria {
  double min_s = 0.0;
  double window_s = 60.0;
  double max_drift_c = 0.1;
  double timeout_s = 3600.0;
};

enum class DriftAction { kFlag, kReject };
std::string_view ToString(DriftAction action) noexcept;  // "flag", "reject"

// [drift]: per run, the paper estimates only when temperature is stationary (change < 1 %):
// |T_end − T_start| / |T_start| (T in °C, as the paper states it) and the same for the resonant
// frequency. A run beyond a limit is flagged (kept, marked) or rejected (not given to the
// estimator).
struct DriftCriteria {
  double max_temperature_change_rel = 0.01;
  std::optional<double> max_frequency_change_rel;  // absent: not checked
  DriftAction action = DriftAction::kFlag;
};

// [capture]: per-run loss allowed; more is an ERROR of the bench (STYLE rule 9), not a FAIL.
struct CaptureCriteria {
  std::int64_t max_sequence_gaps = 0;  // breaks in the sample sequence per run
  std::int64_t max_samples_lost = 0;   // samples missing per run
};

// [adaptive]: a session as short as its verdict allows (issue 27 §1). After each complete run from
// min_runs on (and, with look_interval_s, during each run as it is captured), every unit still
// measuring is estimated and judged as at the end; a unit whose
// verdict can no longer change (the fit acceptable on its runs so far, and every limit proven
// conforming, or one proven non-conforming) takes no further run, and the session ends when no
// unit needs the next one. A misfit, an undecided or a not-yet-evaluable limit never ends a
// session early. Off unless stop_when_decided.
//
// Each look before the last planned run is an interim decision: it is taken with a larger coverage
// factor than the limits file's k, so that looking again and again does not multiply the chance
// of a wrong decision (analysis/interim_looks.hpp). The verdict a decided unit closes with
// is judged with the file's k, as any other.
// At most this many interim looks in a plan (the loader refuses a look_interval_s that makes
// more): each is an estimate at the bench, and their coverage factor's integration grows as n^1.5.
inline constexpr std::size_t kMaxInterimLooks = 400;

// The first look within a run: the first multiple of look_interval_s that is at least as long as
// the shortest run already made (and at least one interval). A run much shorter than the others
// cannot show that one of them is off (its Ω, most of all): at 5 s of a second 20 s run the fit
// absorbed a first run's Ω error of 10 of its std into δ2 (8 std) and flagged none of 10 sessions;
// from 15 s on it flagged all (docs/measurements/2026-12-02-adaptive-looks.md). 0 for no looks.
double FirstLookWithinRunS(double look_interval_s, double shortest_run_before_s);

struct AdaptiveStop {
  bool stop_when_decided = false;
  int min_runs = 1;  // complete runs before the first decision, 1 … the sequence's runs
  // k of the interim looks, in [the limits' k, 6]; absent: derived from the limits' k and the
  // number of interim looks (InterimCoverageFactor).
  std::optional<double> interim_coverage_factor;
  // Looks within a run, every this many seconds of its free run (from the min_runs-th run on):
  // a unit decided during a run stops capturing then, and the run ends once no unit on the table
  // still needs it. 0: looks after runs only. In [1, 3600] when set (each look is an estimate).
  double look_interval_s = 0.0;
  // next_run = "most_informative": after each run, the next is the remaining one that adds most
  // to what the units' verdicts still lack per second of table time (analysis/next_run.hpp);
  // "plan" (default): the file's order.
  bool most_informative_next = false;
};

// [[prompts]]: what the operator must do at a point of the sequence (mount the unit, close the
// lid, connect a cable), shown as a dialog on the panel or a line on the terminal and answered
// "confirm" or "abort". While one is open the table is at zero rate and every gyro stopped; who
// answered and when goes into the record (SessionRecorder::BeginPrompt/EndPrompt).
enum class PromptPoint { kStart, kBeforeRun, kEnd };
inline constexpr std::size_t kMaxPrompts = 64;
// An image is shown beside the text (the panel embeds it in its event: kept small).
inline constexpr std::uintmax_t kMaxPromptImageBytes = 256 * 1024;

struct SequencePrompt {
  std::string id;                        // unique in the sequence: what the answer names
  PromptPoint at = PromptPoint::kStart;  // start: before the warm-up; end: after the last run
  int before_run = 0;  // kBeforeRun: the run's id (its place in [[runs]], 1-based)
  std::string text;
  // Optional: a PNG, JPEG or SVG file in the sequence file's folder or below it (written relative
  // to it; the config copy of a session holds it at the same place). Empty: none.
  std::string image;                 // as written, relative
  std::filesystem::path image_file;  // resolved against the sequence file's folder
  std::string image_sha256;          // of the image's bytes, as loaded ("" without one)

  // "start", "before run 3", "end": where it is asked, for the record and the operator.
  std::string Where() const;
};

struct SequenceConfig {
  std::filesystem::path file;  // where it was loaded from
  std::string sha256_hex;      // SHA-256 of the file's bytes (recorded in the session)

  std::string name;  // [sequence] name (required)
  std::string description;
  SettleCriteria settle;
  SequenceTimeouts timeouts;
  WarmupCriteria warmup;
  DriftCriteria drift;
  CaptureCriteria capture;
  AdaptiveStop adaptive;
  std::vector<SequenceRun> runs;        // in order: run ids 1, 2, ...
  std::vector<SequencePrompt> prompts;  // in file order; asked in that order at each point

  // The prompts asked at `at` (before run `run_id` for kBeforeRun), in file order.
  std::vector<const SequencePrompt*> PromptsAt(PromptPoint at, int run_id = 0) const;

  // The runs as the estimator's design (φ = 0; Ω is the table rate: add the Earth-rate part for a
  // plan that should match a real session).
  std::vector<estimator::RunPlan> ToRunPlans(double omega_offset_rad_s = 0.0) const;
  double TotalFreeRunS() const;
  // The interim looks [adaptive] plans, as information fractions (free-run seconds before the
  // look over TotalFreeRunS), in order: within each run from the min_runs-th on, at every
  // look_interval_s of its free run from FirstLookWithinRunS up to half an interval before its
  // end; after each run from the min_runs-th to the last but one. Empty unless stop_when_decided.
  // At most kMaxInterimLooks. (With next_run = "most_informative" the runs may come in another
  // order; the plan's order is what k_i is computed for.)
  std::vector<double> InterimLookFractions() const;
};

std::expected<SequenceConfig, config_file::ConfigError> LoadSequenceConfig(
    const std::filesystem::path& file);
std::expected<SequenceConfig, config_file::ConfigError> ParseSequenceConfig(
    std::string_view toml_text, const std::filesystem::path& file);

}  // namespace hrgbench::bench
