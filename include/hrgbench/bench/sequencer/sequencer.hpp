#pragma once
// The bench session: the sequence of free runs at set Ω on whatever hardware it is given, recorded
// so that nothing is lost, estimated and judged against the limits.
//
// Per run (issue 4 §2): table to Ω → wait until rate stable (or time out) → configure and excite
// the wave → wait until the electronics report ready → note measured table rate, temperature and
// resonant frequency → release (the acknowledged, timestamped release is t = 0) → capture for the
// run's length on the capture thread (bench/capture.hpp) while this thread streams the samples and
// every raw CAN frame to the record, keeps the table's heartbeat and averages its measured rate →
// stop the gyro → judge the run (losses, temperature and frequency drift) → next run. The Ω written
// for the estimator is the mean measured table rate over the capture plus the Earth-rate component
// on the sensitive axis. Before the first run the gyro must be warm (sequence [warmup]).
//
// Safety (§5): on any fault, timeout or the first interrupt the table is commanded to zero rate
// (RateTable::SafeStop), the gyro to its safe state (Stop), the open run is closed as aborted and
// the session closed with the reason. Outcomes: PASS (every limit met), FAIL (a parameter out of
// its limits: the record names which), ERROR (the bench: timeout, bus-off, Modbus failure, too many
// drops, disk), ABORTED (operator). Exit codes in session_outcome.hpp.
//
// Threads: a session runs on the caller's thread (plus one capture thread per unit and run).
// Every timed wait goes through the hardware's Clock or a driver call, so a simulated station can
// run in virtual time. Nothing here throws across the API except std::bad_alloc.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/analysis/verdict.hpp"
#include "hrgbench/bench/sequencer/operator_prompts.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/hw/can_bus.hpp"
#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/hw/operating_gyro.hpp"
#include "hrgbench/hw/rate_table.hpp"
#include "hrgbench/session/session_outcome.hpp"
#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench {

// One gyro on the table: its electronics and the tap on its bus. Not owned.
struct UnitHardware {
  hw::GyroElectronics* gyro = nullptr;
  // The same electronics as a gyro (their compensation block, their angle output), for tuning;
  // null when they have no operating mode.
  hw::OperatingGyro* operating = nullptr;
  // Optional tap that receives every frame on the gyro's bus (a second socket on the interface, or
  // the virtual bus's monitor endpoint): everything it receives goes to the unit's candump log.
  hw::CanBus* monitor = nullptr;
  // The monitor's receive stamps: on the bench clock (a virtual bus) or, for software stamps, Unix
  // time (SocketCAN: CLOCK_REALTIME). Other stamps (a controller's own clock) are replaced by the
  // bench clock at the time the frame is taken off the monitor.
  bool monitor_stamps_on_bench_clock = true;
  std::string can_interface = "can0";  // name written in the candump log
  // The unit's node id on its bus and the version of the gyro CAN protocol the log speaks
  // (0: not said), recorded with the log (can_log.node, can_log.protocol) for its replay.
  int can_node = 0;
  int can_protocol = 0;
  std::string position;  // the fixture position it sits in ("A", "1")
  // +1: its sensitive axis along the table's axis; −1: against it (mounted upside down). Its Ω,
  // Earth rate and record are in its own frame: −1 × the table's.
  int axis_sign = 1;
};

// What a session runs on: one table and the units on it (a fixture of N positions, one bus each).
// Not owned; all must outlive the session. The table must be connected.
struct BenchHardware {
  hw::RateTable* table = nullptr;
  hw::Clock* clock = nullptr;
  std::vector<UnitHardware> units;  // at least one; the fitted positions in the station's order
};

// What the operator sees, handed to RunnerOptions::on_progress about every progress_period_s.
struct Progress {
  int run = 0;        // 1-based index of the current run in the plan (0 before the first)
  int run_count = 0;  // runs in this invocation (a resume counts only the remaining ones)
  int run_id = 0;     // the run's id in the session
  double omega_rad_s = 0.0;
  // "warm-up", "table" (settling), "excite", "ready", "release", "capture", "stop", "estimate",
  // "prompt" (an operator prompt is open: the table at zero rate, its rate in table_rate_rad_s),
  // "stopping" (after an abort or a fault: the table's rate until it reads zero);
  // every change of phase is reported at once (the period applies within a phase).
  std::string_view phase;
  double elapsed_s = 0.0;    // since the session (or the resume) started, on the hardware clock
  double remaining_s = 0.0;  // rough: the free-run time still to capture plus settling
  // Summed over the units capturing the current run.
  std::uint64_t samples = 0;  // captured in the current run
  std::uint64_t samples_expected = 0;
  std::uint64_t samples_lost = 0;  // sequence gaps + ring overruns in the current run
  int units_active = 0;  // units still in the session (the others ended on their own fault)
  int unit_count = 0;
  double table_rate_rad_s = std::numeric_limits<double>::quiet_NaN();  // last measured, capture
};

struct RunnerOptions {
  std::string unit_serial;       // RunSession's unit; required there
  std::string software_version;  // git describe of the build
  // Who runs (or resumes) it: recorded as every unit's "operator" (resume: in "resumed_at").
  std::string operator_name;
  // RunSession's unit: the truth of a simulated station, recorded under "simulation" (std::nullopt
  // on real hardware).
  std::optional<nlohmann::json> simulation;
  // Incremented by the signal handler per Ctrl-C: the first stops the session safely (ABORTED).
  const std::atomic<int>* interrupts = nullptr;
  // The signal behind the first interrupt (SIGINT: the operator's Ctrl-C or the panel's Abort;
  // SIGTERM: a supervisor or shutdown), for the record's reason; null or 0: the operator.
  const std::atomic<int>* interrupt_signal = nullptr;
  std::function<void(const Progress&)> on_progress;  // runner thread; may be empty
  std::function<void(std::string_view)> on_log;      // plain log lines; may be empty
  // The samples of run `run_id` as they are written to the record (runner thread, between ring
  // drains: must return quickly, never block; the event stream decimates them). May be empty.
  // Called for a session of one unit only (the event stream is one unit's).
  std::function<void(int run_id, std::span<const GyroSampleRecord>)> on_samples;
  // A run as recorded (complete, rejected or aborted) with its sample count. May be empty. One
  // unit only, as on_samples.
  std::function<void(int run_id, const RunEnd&, std::uint64_t samples)> on_run_end;
  // A run as recorded for unit `unit` (the index into the session's units), for every unit of a
  // fixture as of one (a fixture's panel shows each unit's runs). May be empty.
  std::function<void(std::size_t unit, int run_id, const RunEnd&, std::uint64_t samples)>
      on_unit_run_end;
  double progress_period_s = 0.5;
  // Answers the sequence's operator prompts (not owned). A sequence with prompts and no source is
  // refused before anything moves (ERROR).
  PromptAnswers* prompts = nullptr;
  // A prompt shown (reply null) and answered (reply set), for the event stream. May be empty.
  std::function<void(const PromptRequest&, const PromptReply* reply)> on_prompt;
  // Unit `unit` (the index into the session's units; 0 for RunSession) decided at an interim look
  // of the sequence's [adaptive]: it takes no further run. May be empty.
  std::function<void(std::size_t unit, const EarlyEnd& decided)> on_decided;
};

struct SessionResult {
  OutcomeKind outcome = OutcomeKind::kError;
  std::string reason;
  int exit_code = kExitError;
  std::filesystem::path dir;
  std::optional<estimator::EstimateSummary> estimate;  // when the estimator ran
  std::optional<Verdict> verdict;                      // when the estimate was usable
  // The estimate in the field's units (τ, Q, splits, axes, k, pick-off errors), with the f0 the
  // electronics reported; when the estimate was usable.
  std::optional<estimator::EngineeringQuantities> engineering;
  nlohmann::json estimate_json;       // as recorded in session.json (or null)
  std::vector<std::string> warnings;  // flagged runs, estimator warnings
  int complete_runs = 0;
};

// One unit of a session: what it is and where its record goes.
struct UnitSession {
  std::string serial;         // required
  std::filesystem::path dir;  // new and empty (run), or the unit's session to continue (resume)
  std::optional<nlohmann::json> simulation;  // its truth on a simulated station
  // Recorded as "fixture" in its session.json (position, the fixture folder, the other units);
  // std::nullopt for a session of one unit.
  std::optional<nlohmann::json> fixture;
};

// Runs the whole sequence for every unit on the table: the table is sequenced once, and at each Ω
// every unit still in the session is excited, released and captured (one capture thread per unit,
// each with its own ring and drop accounting). Each unit has its own session folder, record,
// estimate and verdict. A unit's own fault (never ready, never warm, stalls, bus-off on its bus,
// too many drops, its record) ends that unit's session as ERROR and the others go on; a table
// fault or an interrupt stops every unit safely, each record saying why. `units[i]` runs on
// `hardware.units[i]`; the result i is its. The config files are copied into every unit's
// <dir>/config/ (so `resume` needs nothing else and the record shows what was run).
std::vector<SessionResult> RunSessions(const BenchConfigs& configs, const BenchHardware& hardware,
                                       const std::vector<UnitSession>& units,
                                       const RunnerOptions& options);

// Continues the units' sessions (each interrupted or failed) with the runs each has not
// completed, using the configs saved in the first unit's <dir>/config/ (loaded by the caller with
// LoadSavedConfigs), then estimates each from all its runs. A run is made if any unit needs it;
// a unit that has it already sits it out.
std::vector<SessionResult> ResumeSessions(const BenchConfigs& configs,
                                          const BenchHardware& hardware,
                                          const std::vector<UnitSession>& units,
                                          const RunnerOptions& options);

// One unit (hardware.units has one): RunSessions with options.unit_serial, options.simulation.
SessionResult RunSession(const BenchConfigs& configs, const BenchHardware& hardware,
                         const std::filesystem::path& dir, const RunnerOptions& options);
SessionResult ResumeSession(const BenchConfigs& configs, const BenchHardware& hardware,
                            const std::filesystem::path& dir, const RunnerOptions& options);

// The configs a session was started with (<dir>/config/{station,sequence,limits}.toml), checked
// against the SHA-256 recorded in session.json.
std::expected<BenchConfigs, std::string> LoadSavedConfigs(const std::filesystem::path& dir);
// The same, checked against `hashes` ({"station", "sequence", "limits"}: hex or null) as recorded
// in `recorded_in` (named in the error): a fixture's own copies, checked against fixture.json.
std::expected<BenchConfigs, std::string> LoadSavedConfigs(const std::filesystem::path& dir,
                                                          const nlohmann::json& hashes,
                                                          const std::string& recorded_in);
// Copies the files `configs` was loaded from into <dir>/config/ (atomically, each).
std::expected<void, std::string> SaveConfigs(const BenchConfigs& configs,
                                             const std::filesystem::path& dir);

}  // namespace hrgbench::bench
