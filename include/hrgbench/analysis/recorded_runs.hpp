#pragma once
// A recorded session's runs as every fit of it takes them, prepared in one place (hrg-estimate,
// the bench's estimate of record, hrg-bench replay, the report):
//  1. in the model's I/Q convention (session::ToRunData conjugates a "plus-sine" record);
//  2. without each run's first samples inside the declared output filter's settling after release
//     (ReleaseSettlingS in output_filter.hpp): at release the filter's state is the held wave's,
//     and its transient is no part of the free-run model. Fitted, those samples were 50–70 σ off
//     and removed as "outliers" on every run of the carrier station, so the outlier count meant
//     nothing; skipped here, a removed outlier is again a real spike.
// What was done is recorded (Json(): the estimate's "preparation" key) and said (notes).
//
// Pure functions; never throw except std::bad_alloc.

#include <cstddef>
#include <expected>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/analysis/output_filter.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/session/run_spool.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench {

// One run's samples not fitted: those with t_s (time since release) below the settling time.
struct ReleaseSkip {
  int run_id = 0;
  std::size_t samples = 0;        // samples skipped
  double first_fitted_t_s = 0.0;  // time since release of the first sample fitted
};

struct PreparedRuns {
  std::vector<estimator::RunData> runs;  // what the fit takes, in load order
  estimator::IqConvention iq_convention = estimator::IqConvention::kMinusSine;  // as recorded
  OutputFilter output_filter;        // as recorded (kNone when not declared)
  double settle_s = 0.0;             // ReleaseSettlingS(output_filter); 0 when none
  std::vector<ReleaseSkip> skipped;  // one per run, in load order
  // The session reader's notes, then one line on the settling skip (when a filter is declared).
  std::vector<std::string> notes;

  // {"iq_convention": "minus-sine", "release_settling": {"output_filter": "4th-order
  // Butterworth, 200 Hz", "fraction": 1e-6, "settle_s": 0.03, "runs": [{"run": 1,
  // "samples_skipped": 30, "first_fitted_t_s": 0.03}, ...]}, "notes": [...]}
  nlohmann::json Json() const;
};

// Skips the samples of `runs` with t_s < settle_s (never below estimator::kMlMinimumSamples left),
// in place.
std::vector<ReleaseSkip> SkipReleaseSettling(double settle_s,
                                             std::vector<estimator::RunData>* runs);
ReleaseSkip SkipReleaseSettling(double settle_s, estimator::RunData* run);

// The loaded runs of `recorded` prepared as above, with the output filter its record declares
// (`electronics`: the same session.json as typed by session::ReadSessionRecord).
PreparedRuns PrepareRecordedRuns(const session::Session& recorded,
                                 const session::ElectronicsRecord& electronics);
// The same, taking the samples out of `recorded` (its loaded_samples are left empty; every other
// field stays): the runs exist once, not twice (docs/estimator/methods.md "Memory").
PreparedRuns PrepareRecordedRuns(session::Session&& recorded,
                                 const session::ElectronicsRecord& electronics);

// The same preparation, each run read, prepared and added to `spool` in turn (one run's samples
// in memory at a time, besides what the spool keeps): for a session of any length. `recorded` is
// the session as ReadSession returned it without samples (options.load_samples false); `options`
// as the read's. The result's `runs` stay empty (they are in the spool); an error names the file
// (a run CSV, the spool's scratch file).
std::expected<PreparedRuns, session::SessionError> SpoolRecordedRuns(
    const std::filesystem::path& dir, const session::Session& recorded,
    const session::ElectronicsRecord& electronics, const session::ReadOptions& options,
    session::RunSpool* spool);

// The declared I/Q convention against the data. Conjugated channels fit the model perfectly
// (estimator/iq_convention.hpp), so the check needs a sign fixed outside the free run: the
// quadrature the bench commanded at release, runs[].plan.{a, b} (model.hpp's orbit, in the
// model's convention). The fitted initial state's K = 2·(x1·x4 − x2·x3) = 2ab has the plan's sign
// when the declaration is right, the opposite when it is wrong; K is unchanged by the reference's
// phase (a common phase of both channels). A run takes part when its plan has |K/S| ≥ 0.05
// (|b| ≥ 0.025·a); it contradicts when its fitted K/S has the other sign and at least half the
// plan's size. A problem (naming the runs and the likely cause) when every run taking part, at
// least one, contradicts; nullopt otherwise (also when the record has no plans).
inline constexpr double kQuadratureSignMinimum = 0.05;
std::optional<std::string> IqConventionContradiction(const session::SessionRecord& record,
                                                     const estimator::EstimateSummary& summary);

// Adds that problem, when there is one, to summary->diagnostics.problems and ->warnings (so the
// fit is not acceptable and the record says why).
void NameIqConventionContradiction(const session::SessionRecord& record,
                                   estimator::EstimateSummary* summary);

}  // namespace hrgbench::bench
