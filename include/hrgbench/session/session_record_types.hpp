#pragma once
// The data a SessionRecorder takes in: what is planned (SessionHeader, PlannedRun), what happened
// at a run's release (RunStart), each sample (GyroSampleRecord), how a run ended (RunEnd), and its
// errors (RecordError). Plain values; see session_recorder.hpp for the files they end up in.
//
// Units are in the names (STYLE rule 11). Non-finite metadata (a temperature that was not
// measured) is written as JSON null; non-finite *sample* values are refused, because the run CSV
// format rejects them.

#include <cstdint>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hrgbench::bench {

enum class RecordErrorKind {
  kInvalidArgument,    // a value the record cannot hold (bad run id, non-finite sample, ...)
  kWrongState,         // call out of order: BeginRun while a run is open, EndRun without one, ...
  kDirectoryNotEmpty,  // Create() on a directory that already holds something
  kBadSession,         // OpenForResume(): no session.json, or not one this recorder wrote
  kIo,                 // the file system refused: disk full (ENOSPC, EFBIG), read-only, EIO, ...
};

struct RecordError {
  RecordErrorKind kind = RecordErrorKind::kIo;
  std::filesystem::path file;  // the file or directory at fault (may be empty)
  std::string message;         // what went wrong, with the system's reason for kIo
  // "<file>: <message>"
  std::string ToString() const;
};

// One run as the sequence file plans it.
struct PlannedRun {
  int id = 0;                          // 1-based, unique in the session; names runs/run-NNN.csv
  double commanded_omega_rad_s = 0.0;  // table rate to command
  double a = 1.0;                      // wave state to excite (model.hpp's Orbit at release)
  double b = 0.0;
  double theta_rad = 0.0;
  double free_run_s = 0.0;      // capture length after release, > 0
  double sample_rate_hz = 0.0;  // > 0
};

struct ConfigHashes {
  std::string station_sha256;  // lower-case hex SHA-256 of each file's bytes, as loaded
  std::string sequence_sha256;
  std::string limits_sha256;  // empty when no limits file was given (JSON null)
};

struct SessionHeader {
  std::string unit_serial;   // required, non-empty
  std::string station_name;  // required, non-empty
  // Who ran it (`hrg-bench run --operator`, the panel's operator field), recorded as "operator";
  // empty: not recorded (the key is left out, as in records from before it was written).
  std::string operator_name;
  std::string software_version;  // git describe of the build (HRGBENCH_GIT_DESCRIBE)
  ConfigHashes config_sha256;
  // As the capture set it up, e.g. "SCHED_FIFO 80 granted, mlockall granted" or
  // "not permitted: running without SCHED_FIFO (EPERM)".
  std::string realtime_status;
  std::vector<PlannedRun> runs;  // at least one; session.json lists them in this order
  // Simulated station: the simulator's truth (parameters, seed), recorded as "simulation".
  std::optional<nlohmann::json> simulation;
  // What the station declares about the gyro's electronics, recorded as "electronics" (e.g. its
  // output filter, which sets the noise shape the fit assumes: output_filter.hpp).
  std::optional<nlohmann::json> electronics;
  // Interface name written into every candump log line ("can0", "vcan0", "sim0").
  std::string can_interface = "can0";
  // The unit's node id on that bus and the gyro CAN protocol's version (0: not said), recorded as
  // can_log.node and can_log.protocol.
  int can_node = 0;
  int can_protocol = 0;
  // A unit of a fixture session: its position and the units beside it, recorded as "fixture".
  std::optional<nlohmann::json> fixture;
  // Files written into the folder (path relative to it, contents) before session.json, so that a
  // session.json never exists without them: the config copies `resume` loads (config/*.toml).
  std::vector<std::pair<std::string, std::string>> files_first;
};

// Conditions at the release of a run (t = 0).
struct RunStart {
  double commanded_omega_rad_s = 0.0;
  double measured_omega_rad_s = std::numeric_limits<double>::quiet_NaN();  // table, settled
  double earth_rate_rad_s = 0.0;  // Earth-rate component on the sensitive axis
  double temperature_c = std::numeric_limits<double>::quiet_NaN();
  double resonant_frequency_hz = std::numeric_limits<double>::quiet_NaN();
  std::int64_t release_t_ns = 0;  // acknowledged release stamp, receive time base
  // Optional per-sample columns of this run's CSV; when set, every sample must carry a finite
  // value for it.
  bool with_measured_omega = false;      // column omega_meas_rad_s
  bool with_temperature = false;         // column temp_c
  bool with_resonant_frequency = false;  // column freq_hz
};

// One sample as the run CSV stores it.
struct GyroSampleRecord {
  std::uint32_t seq = 0;  // electronics' sample number since release (column seq)
  double t_s = 0.0;       // s since release; strictly increasing within a run
  double y[4] = {0.0, 0.0, 0.0, 0.0};
  double measured_omega_rad_s = std::numeric_limits<double>::quiet_NaN();  // if with_measured_omega
  double temperature_c = std::numeric_limits<double>::quiet_NaN();         // if with_temperature
  // If with_resonant_frequency.
  double resonant_frequency_hz = std::numeric_limits<double>::quiet_NaN();
};

// Run status strings in session.json. Only kRunComplete runs are read by the estimator.
inline constexpr const char* kRunPlanned = "planned";
inline constexpr const char* kRunRunning = "running";  // open, or the process died
inline constexpr const char* kRunComplete = "complete";
inline constexpr const char* kRunAborted = "aborted";          // stopped early (fault, Ctrl-C)
inline constexpr const char* kRunRejected = "rejected";        // captured, but unfit (drift, drops)
inline constexpr const char* kRunInterrupted = "interrupted";  // was running when the process died

struct RunEnd {
  std::string status = kRunComplete;  // kRunComplete, kRunAborted or kRunRejected
  std::string reason;                 // required unless complete
  // Ω for the estimator: the table's mean rate over the capture + the Earth-rate component,
  // measured as omega_source says (below). Must be finite for a complete run; otherwise NaN means
  // "commanded Ω" in session.json.
  double omega_rad_s = std::numeric_limits<double>::quiet_NaN();
  // How well that Ω is known (rad/s) and from how many table readings. With the production
  // sequence, an Ω error of 3e-7 rad/s already biases δ3…δ6 by ~4 of their std, so the record
  // keeps it. NaN / 0 when not measured.
  double omega_std_error_rad_s = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t omega_readings = 0;
  // Which measurement the three above are: "angle" or "rate" (bench/run_omega.hpp); empty when
  // neither was made (a run that ended before its capture).
  std::string omega_source;
  // Both measurements, each + the Earth-rate component, so nothing is lost whichever was used:
  // the mean of the rate readings and its standard error; the angle's line fit and its standard
  // error (NaN / 0 when the table reports no angle or it was not read).
  double omega_rate_rad_s = std::numeric_limits<double>::quiet_NaN();
  double omega_rate_std_error_rad_s = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t omega_rate_readings = 0;
  double omega_angle_rad_s = std::numeric_limits<double>::quiet_NaN();
  double omega_angle_std_error_rad_s = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t omega_angle_readings = 0;
  double temperature_start_c = std::numeric_limits<double>::quiet_NaN();
  double temperature_end_c = std::numeric_limits<double>::quiet_NaN();
  double frequency_start_hz = std::numeric_limits<double>::quiet_NaN();
  double frequency_end_hz = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t sequence_gaps = 0;
  std::uint64_t kernel_drops = 0;
  std::uint64_t bad_frames = 0;
  // The electronics' reference phase (drivers/gyro_can README "Reference phase"): samples turned
  // back by it (0: not reported, y as demodulated), and samples its report was lost for.
  std::uint64_t reference_phase_undone_samples = 0;
  std::uint64_t reference_phases_missing = 0;
  // The sequence's [adaptive] decided the unit at a look during this run: its capture stopped
  // there, short of the planned length, and the run is complete with what it holds. NaN / empty:
  // the run went its planned length (or ended for the reason above).
  double decided_at_s = std::numeric_limits<double>::quiet_NaN();  // free-run s at the look
  std::string decided_why;  // "every limit decided", "delta2 proven non-conforming"
  double decided_coverage_factor = std::numeric_limits<double>::quiet_NaN();  // the look's k_i
};

// An operator prompt of the sequence (config/sequence_config.hpp SequencePrompt) as it was shown
// (SessionRecorder::BeginPrompt: stamped "shown") and answered (EndPrompt: stamped "answered").
struct PromptShown {
  std::string id;            // the sequence's prompt id
  std::string at;            // "start", "before run 3", "end"
  std::string text;          // as shown
  std::string image_sha256;  // of the image shown beside it; empty: none
};

// Answers in session.json: the operator confirmed it, or chose abort, or the prompt was still open
// when the session stopped (an Abort, Ctrl-C, a fault).
inline constexpr const char* kPromptConfirmed = "confirmed";
inline constexpr const char* kPromptAborted = "aborted";
inline constexpr const char* kPromptInterrupted = "interrupted";

struct PromptAnswered {
  std::string answer = kPromptConfirmed;  // one of the kPrompt* strings
  std::string by;   // the operator who answered; empty when nobody did (interrupted)
  std::string how;  // "panel", "terminal" or "auto" (`--prompts confirm`: no person answered)
};

// A run as the record holds it now (for resume and the progress display).
struct RecordedRun {
  PlannedRun plan;
  std::string status;  // one of the kRun* strings
  std::string file;    // "runs/run-003.csv"
  int attempts = 0;    // earlier attempts kept aside (interrupted, aborted, rejected)
};

}  // namespace hrgbench::bench
