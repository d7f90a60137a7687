#pragma once
// The key names of session.json, spelled once. The typed reader (session_record.hpp) reads through
// these; the writers (session_writer.cpp, the recorder's session_document.cpp) may use them too, so
// a renamed key is renamed on both sides at once. Only the record's own keys are here: the event
// stream and the panel's HTTP JSON are other formats.
//
// The schema, as the recorder writes it (every number that was not measured is null):
//   format, version, state ("running" | "closed"), unit.serial, operator (string or {name}),
//   station.name, software.version, realtime, config_sha256.{station, sequence, limits},
//   started / ended {utc, monotonic_ns}, sample_rate_hz, can_log.{file, interface, node, protocol},
//   electronics {iq_convention, output_filter, pickoff, ...} (the station's declaration),
//   simulation (the simulator's truth: opaque), fixture {position, ...} (opaque),
//   runs[] {id, file, omega_rad_s, status, plan {...}, start {...}, end {...}, attempts [...]},
//   outcome {kind, exit_code, reason, failed_parameters [...], estimate {...}, verdict {...,
//   decision {...}, retest, limits [{..., rule, zone, interval_min, ...}]}},
//   resumed_at [...], prompts [{id, at, text, image_sha256, shown, answer, by, how, answered}],
//   results (the upload mark).

namespace hrgbench::session::keys {

// Top level.
inline constexpr const char* kFormat = "format";
inline constexpr const char* kVersion = "version";
inline constexpr const char* kState = "state";
inline constexpr const char* kUnit = "unit";
inline constexpr const char* kSerial = "serial";
inline constexpr const char* kOperator = "operator";
inline constexpr const char* kStation = "station";
inline constexpr const char* kName = "name";
inline constexpr const char* kSoftware = "software";
inline constexpr const char* kRealtime = "realtime";
inline constexpr const char* kConfigSha256 = "config_sha256";
inline constexpr const char* kSequence = "sequence";
inline constexpr const char* kLimits = "limits";
inline constexpr const char* kStarted = "started";
inline constexpr const char* kEnded = "ended";
inline constexpr const char* kUtc = "utc";
inline constexpr const char* kMonotonicNs = "monotonic_ns";
inline constexpr const char* kSampleRateHz = "sample_rate_hz";
inline constexpr const char* kCanLog = "can_log";
inline constexpr const char* kInterface = "interface";
inline constexpr const char* kNode = "node";
inline constexpr const char* kProtocol = "protocol";
inline constexpr const char* kElectronics = "electronics";
inline constexpr const char* kIqConvention = "iq_convention";
// electronics (session/electronics.hpp: the station's declaration).
inline constexpr const char* kOutputFilter = "output_filter";
inline constexpr const char* kFilterNone = "none";
inline constexpr const char* kFilterButterworth = "butterworth";
inline constexpr const char* kOrder = "order";
inline constexpr const char* kCutoffHz = "cutoff_hz";
inline constexpr const char* kPickoff = "pickoff";
inline constexpr const char* kCrossTalkStage = "cross_talk_stage";
inline constexpr const char* kUnmodelledCouplingBoundRad = "unmodelled_coupling_bound_rad";
inline constexpr const char* kSimulation = "simulation";
inline constexpr const char* kFixture = "fixture";
inline constexpr const char* kFixturePosition = "position";  // in fixture
inline constexpr const char* kRuns = "runs";
inline constexpr const char* kOutcome = "outcome";
inline constexpr const char* kResumedAt = "resumed_at";
inline constexpr const char* kResults = "results";
inline constexpr const char* kPrompts = "prompts";

// An operator prompt (id, reason as above).
inline constexpr const char* kAt = "at";
inline constexpr const char* kText = "text";
inline constexpr const char* kImageSha256 = "image_sha256";
inline constexpr const char* kShown = "shown";
inline constexpr const char* kAnswer = "answer";
inline constexpr const char* kBy = "by";
inline constexpr const char* kHow = "how";
inline constexpr const char* kAnswered = "answered";

// State values.
inline constexpr const char* kStateRunning = "running";
inline constexpr const char* kStateClosed = "closed";

// A run.
inline constexpr const char* kId = "id";
inline constexpr const char* kFile = "file";
inline constexpr const char* kOmegaRadS = "omega_rad_s";
inline constexpr const char* kStatus = "status";
inline constexpr const char* kPlan = "plan";
inline constexpr const char* kStart = "start";
inline constexpr const char* kEnd = "end";
inline constexpr const char* kAttempts = "attempts";
inline constexpr const char* kReason = "reason";
inline constexpr const char* kSamples = "samples";

// The outcome.
inline constexpr const char* kKind = "kind";
inline constexpr const char* kExitCode = "exit_code";
inline constexpr const char* kFailedParameters = "failed_parameters";
inline constexpr const char* kEstimate = "estimate";
inline constexpr const char* kVerdict = "verdict";
// outcome.ended_early: {after_run, planned_runs, why, interim_coverage_factor, within_run_s}
// (session_outcome.hpp EarlyEnd).
inline constexpr const char* kEndedEarly = "ended_early";
inline constexpr const char* kAfterRun = "after_run";
inline constexpr const char* kPlannedRuns = "planned_runs";
inline constexpr const char* kWhy = "why";
inline constexpr const char* kInterimCoverageFactor = "interim_coverage_factor";
inline constexpr const char* kWithinRunS = "within_run_s";
// runs[i].end.decided: {at_s, why, interim_coverage_factor}: the run's capture stopped at the
// look that decided the unit (session_record_types.hpp RunEnd::decided_at_s).
inline constexpr const char* kDecided = "decided";
inline constexpr const char* kAtS = "at_s";
// The estimate of record's nuisance per run (what the report needs to draw the recorded fit).
inline constexpr const char* kFittedRuns = "fitted_runs";

// Inside the outcome, the estimate, the verdict and a run (the report's data-source pointers are
// built from these: report/page_pointer.hpp).
inline constexpr const char* kValue = "value";
inline constexpr const char* kStd = "std";
inline constexpr const char* kMin = "min";
inline constexpr const char* kMax = "max";
inline constexpr const char* kMessage = "message";
inline constexpr const char* kNote = "note";
inline constexpr const char* kMethod = "method";
inline constexpr const char* kDelta = "delta";
inline constexpr const char* kDeltaStd = "delta_std";
inline constexpr const char* kXi = "xi";
inline constexpr const char* kXiStd = "xi_std";
inline constexpr const char* kResidualRms = "residual_rms";
inline constexpr const char* kNoiseSigma = "noise_sigma";
inline constexpr const char* kSamplesUsed = "samples_used";
inline constexpr const char* kIterations = "iterations";
inline constexpr const char* kTruth = "truth";
inline constexpr const char* kFit = "fit";
inline constexpr const char* kCovariance = "covariance";  // in fit: "white" | "sandwich"
inline constexpr const char* kRun = "run";
inline constexpr const char* kResidualRatio = "residual_ratio";
inline constexpr const char* kWhitenessZ = "whiteness_z";
inline constexpr const char* kOutliersRemoved = "outliers_removed";
inline constexpr const char* kOmegaOffsetInStd = "omega_offset_in_std";
inline constexpr const char* kEngineering = "engineering";
inline constexpr const char* kFrequencyHz = "frequency_hz";
inline constexpr const char* kFrequencySource = "frequency_source";
inline constexpr const char* kCoverageFactor = "coverage_factor";
inline constexpr const char* kLimitations = "limitations";
inline constexpr const char* kQuantities = "quantities";
inline constexpr const char* kLabel = "label";
inline constexpr const char* kDetermined = "determined";
inline constexpr const char* kBudget = "budget";
inline constexpr const char* kSource = "source";
inline constexpr const char* kStandardUncertainty = "standard_uncertainty";
inline constexpr const char* kType = "type";
inline constexpr const char* kOverall = "overall";
inline constexpr const char* kFitAcceptable = "fit_acceptable";
inline constexpr const char* kFitChecks = "fit_checks";
inline constexpr const char* kQuantity = "quantity";
// The decision rule (analysis/verdict.hpp, config/decision_rule.hpp): verdict.decision {rule,
// coverage_factor, max_uncertainty_ratio}, verdict.retest, and per limit rule, zone,
// coverage_factor, expanded_uncertainty, interval_min/max, acceptance_min/max, retest.
inline constexpr const char* kDecision = "decision";
inline constexpr const char* kRule = "rule";
inline constexpr const char* kMaxUncertaintyRatio = "max_uncertainty_ratio";
inline constexpr const char* kRetest = "retest";
inline constexpr const char* kZone = "zone";
inline constexpr const char* kExpandedUncertainty = "expanded_uncertainty";
inline constexpr const char* kIntervalMin = "interval_min";
inline constexpr const char* kIntervalMax = "interval_max";
inline constexpr const char* kAcceptanceMin = "acceptance_min";
inline constexpr const char* kAcceptanceMax = "acceptance_max";
// A run's end and start (bench::RunEnd / RunStart as the recorder writes them).
inline constexpr const char* kSequenceGaps = "sequence_gaps";
inline constexpr const char* kKernelDrops = "kernel_drops";
inline constexpr const char* kBadFrames = "bad_frames";
inline constexpr const char* kOmegaStdErrorRadS = "omega_std_error_rad_s";
inline constexpr const char* kOmegaRateStdErrorRadS = "omega_rate_std_error_rad_s";
inline constexpr const char* kTemperatureStartC = "temperature_start_c";
inline constexpr const char* kTemperatureEndC = "temperature_end_c";
inline constexpr const char* kFrequencyStartHz = "frequency_start_hz";
inline constexpr const char* kFrequencyEndHz = "frequency_end_hz";
inline constexpr const char* kResonantFrequencyHz = "resonant_frequency_hz";
// hrg-sim's sessions (app/sim_session.cpp): top-level provenance instead of software /
// config_sha256.
inline constexpr const char* kSoftwareVersion = "software_version";
inline constexpr const char* kSpecSha256 = "spec_sha256";
inline constexpr const char* kDescription = "description";

}  // namespace hrgbench::session::keys
