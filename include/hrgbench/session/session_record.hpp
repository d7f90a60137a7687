#pragma once
// The closed (or still running) session as every program reads it: one typed value read from
// <session>/session.json by ONE function, ReadSessionRecord. Programs read fields, never keys
// (STYLE rule 13); the key names live in session_record_keys.hpp, shared with the writers.
//
// What is typed: everything a reader of the record uses (report, results store, replay, panel,
// resume, fixture, the estimate of record's inputs, and the station's electronics declaration:
// its I/Q convention, output filter and pick-off, session/electronics.hpp). What stays raw JSON:
// what another layer owns and only passes through or interprets itself: "simulation" (the
// simulator's truth), "fixture", and the estimate and verdict objects as a whole (for pages that
// show every field the estimator wrote). `document` is the whole file, unknown keys included, for
// the writer and for the results store's content hash.
//
// Optional fields: std::optional when the key may be absent in a record of an older bench or a
// session still running; numbers the bench writes as null (not measured) read as NaN. A key that
// is present with the wrong type, or a value out of its range, is an error naming the file, the
// field path (jq style, 0-based: "runs[2].end.omega_rad_s") and the value, once, here.
//
// Bounds: those of ReadSession (session.hpp: size, depth, number of runs, name fields), which this
// reader calls first. Thread-safe (no shared state); never throws (except std::bad_alloc).

#include <array>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/estimator/iq_convention.hpp"
#include "hrgbench/session/electronics.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_outcome.hpp"
#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::session {

inline constexpr double kNotRecorded = std::numeric_limits<double>::quiet_NaN();

// started / ended / a run's start and end: wall clock and the bench's monotonic clock.
struct TimeStampRecord {
  std::string utc;                           // ISO 8601 as written, "" when absent
  std::optional<std::int64_t> monotonic_ns;  // CLOCK_MONOTONIC, absent in hand-made records
};

struct ConfigHashesRecord {
  std::string station_sha256;  // lower-case hex; "" when absent
  std::string sequence_sha256;
  std::string limits_sha256;  // "" when no limits file was given (null)
  bool recorded = false;      // the config_sha256 object is there (hrg-sim writes spec_sha256)
};

// can_log: where the raw CAN traffic is and what it speaks.
struct CanLogRecord {
  std::string file;                      // "can/session.log"; "" when absent
  std::string interface_name;            // "can0", "vcan0", "sim0"; "" when absent
  std::optional<std::int64_t> node;      // the unit's node id; absent before protocol v2
  std::optional<std::int64_t> protocol;  // gyro CAN protocol version; absent: v1
};

// electronics: what the station declared of its gyro's electronics (session/electronics.hpp; the
// analysis turns it into the noise shape, the release settling and the budget: output_filter.hpp,
// engineering_of_record.hpp). Validated here: a declaration this reader does not know is an error
// naming the field and the value (guessing would change the estimate silently).
struct ElectronicsRecord {
  // electronics.iq_convention ("minus-sine" | "plus-sine"); minus-sine when absent (a note says
  // so).
  estimator::IqConvention iq_convention = estimator::IqConvention::kMinusSine;
  // electronics.output_filter: {"kind": "none"} or {"kind": "butterworth", "order": 1 ...
  // estimator::kMaxButterworthOrder, "cutoff_hz": > 0}. Absent: none declared (records before the
  // declaration existed, hrg-sim sessions), which the analysis takes as no filter.
  std::optional<bench::OutputFilter> output_filter;
  // electronics.pickoff: {"cross_talk_stage": "midway" | "before_gain" | "after_gain",
  // "unmodelled_coupling_bound_rad": 0 ... bench::kMaxCouplingBoundRad}; a member absent keeps the
  // PickoffDeclaration default. Absent: recorded before the pick-off was declared.
  std::optional<bench::PickoffDeclaration> pickoff;
};

// runs[i].start: the conditions at release (bench::RunStart) and when it was.
struct RunStartRecord {
  bench::RunStart values;  // with_measured_omega / _temperature / _resonant_frequency: not
                           // recorded (false); the run CSV's header says which columns it has
  TimeStampRecord at;
};

// runs[i].end: how the run ended (bench::RunEnd) and when. A recorder error writes only status
// and reason: every other number is then NaN / 0.
struct RunEndRecord {
  bench::RunEnd values;
  std::optional<std::uint64_t> samples;  // absent in an end written by a recorder error
  TimeStampRecord at;
};

// runs[i].attempts[k]: an earlier attempt kept aside (interrupted, aborted, rejected).
struct AttemptRecord {
  std::string status;
  std::string file;  // where its data was moved; "" when none was kept
  std::optional<RunStartRecord> start;
  std::optional<RunEndRecord> end;
};

struct RunRecord {
  int id = 0;
  std::string file;        // relative to the session directory
  double omega_rad_s = 0;  // the Ω given to the estimator (commanded until the run ends)
  std::string status;      // bench::kRun* strings
  // absent only in records not written by the recorder; a field it lacks (hand-made records) or
  // holds as null is NaN
  std::optional<bench::PlannedRun> plan;
  std::optional<RunStartRecord> start;
  std::optional<RunEndRecord> end;
  std::vector<AttemptRecord> attempts;
};

// outcome.estimate.engineering.quantities[k].budget[c]: one component of the quantity's
// uncertainty budget (GUM), as estimate_report_json.cpp writes it.
struct UncertaintyComponentRecord {
  std::string source;
  std::string type;                            // "A" (from the data) or "B" (a model)
  double standard_uncertainty = kNotRecorded;  // NaN: not evaluated (null)
  std::string note;
};

// outcome.estimate.fit.runs[k]: one run's fit diagnostics (the numbers the report shows).
struct FitRunRecord {
  int run = 0;  // the run id
  double residual_rms = kNotRecorded;
  double noise_sigma = kNotRecorded;
  double residual_ratio = kNotRecorded;
  double whiteness_z = kNotRecorded;
  double outliers_removed = kNotRecorded;  // a count; NaN when absent
  double omega_offset_in_std = kNotRecorded;
};

// outcome.estimate.engineering.quantities[k]
struct EngineeringQuantityRecord {
  std::string name;  // "tau_s", "q_factor", ...
  std::string label;
  std::string unit;
  double value = kNotRecorded;
  double std = kNotRecorded;
  bool determined = false;
  std::string note;
  std::vector<UncertaintyComponentRecord> budget;  // largest first, as recorded; empty if none
};

// The per-run nuisance of the estimate of record (estimator::RunNuisanceEstimate): with δ and ξ it
// gives the fitted model of the run (fitted_output.hpp), so the report draws the recorded fit
// without re-running it. Recorded since the report stopped re-running the estimate.
struct FittedRunRecord {
  int run_id = 0;
  std::array<double, 4> initial_state{kNotRecorded, kNotRecorded, kNotRecorded, kNotRecorded};
  std::vector<double> phase_coefficients;  // q_1 … q_D, rad/s^j
  double omega_offset_rad_s = 0.0;
};

// outcome.estimate (bench/estimate_report_json.hpp writes it): the numbers readers use.
struct EstimateRecord {
  std::string method;       // "ml", "paper", ...; "" when absent
  std::string termination;  // estimator::ToString(Termination); "" when absent
  int iterations = 0;
  std::int64_t samples_used = 0;
  int phase_degree = 0;  // fit.phase_degree: D of the common phase (0: none)
  // fit.covariance: "white" (σ̂²(JᵀJ)⁻¹) or "sandwich" (coloured residuals); "" when absent.
  std::string covariance_kind;
  std::array<double, 6> delta;  // NaN where absent or null
  std::array<double, 6> delta_std;
  std::array<double, 4> xi;
  std::array<double, 4> xi_std;
  double residual_rms = kNotRecorded;
  double noise_sigma = kNotRecorded;
  std::vector<std::string> warnings;
  // engineering.frequency_hz and the quantities in the estimator's order (empty when absent).
  double engineering_frequency_hz = kNotRecorded;
  std::vector<EngineeringQuantityRecord> engineering;
  bool engineering_recorded = false;         // the engineering object is there (maybe {error})
  std::string engineering_frequency_source;  // where f0 came from; "" when absent
  double engineering_coverage_factor = kNotRecorded;  // k of U = k·u_c
  std::vector<std::string> engineering_limitations;
  bool delta_recorded = false;         // the delta key is there (its components may be null)
  std::vector<FitRunRecord> fit_runs;  // fit.runs, in the recorded order
  // fit.limits, as the bench judged with (NaN when absent).
  double fit_residual_ratio_max = kNotRecorded;
  double fit_whiteness_z_max = kNotRecorded;
  double fit_omega_offset_max_in_std = kNotRecorded;
  // fitted_runs: empty for a record from before it was kept (the report then re-runs the fit),
  // and for an estimate that gave no nuisance (not usable, or a method without it).
  std::vector<FittedRunRecord> fitted_runs;
  bool fitted_runs_recorded = false;  // the key is there (recorded by this bench or a later one)
  // truth.delta / truth.xi (simulated sessions), NaN when absent.
  std::optional<std::array<double, 6>> truth_delta;
  std::optional<std::array<double, 4>> truth_xi;

  EstimateRecord() {
    delta.fill(kNotRecorded);
    delta_std.fill(kNotRecorded);
    xi.fill(kNotRecorded);
    xi_std.fill(kNotRecorded);
  }
};

// outcome.verdict.limits[k] and fit_checks[k] (bench/verdict_json.hpp writes them).
struct LimitRowRecord {
  std::string quantity;
  std::string status;  // "PASS", "FAIL", "NOT_EVALUATED", ...
  double value = kNotRecorded, std = kNotRecorded;
  double min = kNotRecorded, max = kNotRecorded;  // NaN: no bound
  std::string message;
  // The decision (analysis/verdict.hpp); ""/NaN/nullopt in records from before [decision].
  std::string rule;  // "guarded_acceptance_retest" | "guarded_acceptance_reject" | ...
  std::string zone;  // "conforming" | "non_conforming" | "undecided" | "not_judged"
  double coverage_factor = kNotRecorded;
  double expanded_uncertainty = kNotRecorded;                           // U = k·u
  double interval_min = kNotRecorded, interval_max = kNotRecorded;      // v ∓ U
  double acceptance_min = kNotRecorded, acceptance_max = kNotRecorded;  // the guarded limits
  std::optional<bool> retest;
};
struct FitCheckRecord {
  int run = 0;
  std::string name;
  std::string status;
  double value = kNotRecorded, max = kNotRecorded;
  std::string message;
};
struct VerdictRecord {
  std::string overall;  // "PASS" | "FAIL" | "NOT EVALUATED"; "" when absent
  std::optional<bool> fit_acceptable;
  std::vector<FitCheckRecord> fit_checks;
  std::vector<LimitRowRecord> limits;
  // decision.{rule, coverage_factor, max_uncertainty_ratio} and retest; ""/NaN/nullopt in records
  // from before [decision].
  std::string decision_rule;
  double decision_coverage_factor = kNotRecorded;
  double decision_max_uncertainty_ratio = kNotRecorded;  // simple acceptance only
  std::optional<bool> retest;
};

struct OutcomeRecord {
  bench::OutcomeKind kind = bench::OutcomeKind::kError;
  std::optional<int> exit_code;
  std::string reason;
  std::vector<bench::FailedParameter> failed_parameters;
  std::optional<EstimateRecord> estimate;
  std::optional<VerdictRecord> verdict;
  std::optional<bench::EarlyEnd> ended_early;  // the sequence's [adaptive] ended it early
  // The estimate and verdict objects verbatim (null when absent), for pages that show them whole.
  nlohmann::json estimate_json;
  nlohmann::json verdict_json;
};

// prompts[i]: an operator prompt as shown and answered (session_record_types.hpp PromptShown,
// PromptAnswered); answer "" while it was open (the process died with it open).
struct PromptRecord {
  std::string id, at, text, image_sha256;
  std::optional<TimeStampRecord> shown, answered;
  std::string answer;  // bench::kPromptConfirmed | kPromptAborted | kPromptInterrupted | ""
  std::string by, how, reason;
};

struct SessionRecord {
  std::filesystem::path file;  // the session.json read ("" when read from a document)
  std::string format;          // session::kFormatName
  int version = 0;
  std::string state;  // keys::kStateRunning | kStateClosed; "" in hand-made records
  std::string unit_serial;
  std::string operator_name;  // "operator" (a string or {name}); "" when not recorded
  std::string station_name;   // station.name; "" when absent
  // software.version, or hrg-sim's top-level software_version; "" when neither
  std::string software_version;
  std::string spec_sha256;  // hrg-sim's top-level spec_sha256 (instead of config_sha256); ""
  std::string description;  // hrg-sim's top-level description; "" when absent
  ConfigHashesRecord config_sha256;
  std::optional<TimeStampRecord> started, ended;
  std::string realtime_status;
  double sample_rate_hz = 0.0;
  estimator::IqConvention iq_convention = estimator::IqConvention::kMinusSine;  // = electronics'
  std::optional<CanLogRecord> can_log;  // absent in records older than the CAN log
  ElectronicsRecord electronics;
  // Opaque pass-through (owners elsewhere; null when absent): see the file comment.
  nlohmann::json simulation;
  // simulation.delta / simulation.xi: the simulator's truth (NaN where null), when recorded.
  std::optional<std::array<double, 6>> simulation_delta;
  std::optional<std::array<double, 4>> simulation_xi;
  nlohmann::json fixture;
  // fixture.position: the fitted position the unit sat in; "" when it was not on a fixture.
  std::string fixture_position;
  std::vector<RunRecord> runs;
  std::vector<PromptRecord> prompts;     // in the order they were shown (resumes included)
  std::optional<OutcomeRecord> outcome;  // absent while running or after a crash
  nlohmann::json results;                // the upload mark; null when not uploaded
  nlohmann::json document;               // the whole session.json
  std::vector<std::string> notes;        // the base reader's notes (iq convention assumed, ...)
  // ReadSession's warnings for the same file: "run 3 skipped: status 'aborted'" per run that is
  // not complete (the estimate of record and the report do not read it).
  std::vector<std::string> warnings;

  bool Closed() const { return outcome.has_value(); }
  // The run with this id, or nullptr.
  const RunRecord* Run(int id) const;
};

// Reads and validates `dir`/session.json (no run data). Errors as ReadSession's (file, line,
// field, message with the value).
std::expected<SessionRecord, SessionError> ReadSessionRecord(const std::filesystem::path& dir);

// The same validation of a document already parsed (e.g. one the recorder holds); `file` names it
// in errors. Lines are 0 (the text is not at hand).
std::expected<SessionRecord, SessionError> ReadSessionRecord(const nlohmann::json& document,
                                                             const std::filesystem::path& file);

}  // namespace hrgbench::session
