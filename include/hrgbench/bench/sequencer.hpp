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
// Threads: RunSession runs on the caller's thread (plus the capture thread it starts per run).
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

#include "hrgbench/bench/bench_configs.hpp"
#include "hrgbench/bench/session_outcome.hpp"
#include "hrgbench/bench/session_record_types.hpp"
#include "hrgbench/bench/verdict.hpp"
#include "hrgbench/estimator/summary.hpp"
#include "hrgbench/hw/can_bus.hpp"
#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::bench {

// What the session runs on. Not owned; all must outlive RunSession. The table must be connected.
struct BenchHardware {
  hw::RateTable* table = nullptr;
  hw::GyroElectronics* gyro = nullptr;
  hw::Clock* clock = nullptr;
  // Optional tap that receives every frame on the gyro's bus (a second socket on the interface, or
  // the virtual bus's monitor endpoint): everything it receives goes to the candump log.
  hw::CanBus* monitor = nullptr;
  // The monitor's receive stamps: on `clock` (a virtual bus) or, for software stamps, Unix time
  // (SocketCAN: CLOCK_REALTIME). Other stamps (a controller's own clock) are replaced by the
  // bench clock at the time the frame is taken off the monitor.
  bool monitor_stamps_on_bench_clock = true;
  std::string can_interface = "can0";  // name written in the candump log
};

// What the operator sees, handed to RunnerOptions::on_progress about every progress_period_s.
struct Progress {
  int run = 0;        // 1-based index of the current run in the plan (0 before the first)
  int run_count = 0;  // runs in this invocation (a resume counts only the remaining ones)
  int run_id = 0;     // the run's id in the session
  double omega_rad_s = 0.0;
  // "warm-up", "table" (settling), "excite", "ready", "release", "capture", "stop", "estimate";
  // every change of phase is reported at once (the period applies within a phase).
  std::string_view phase;
  double elapsed_s = 0.0;     // since the session (or the resume) started, on the hardware clock
  double remaining_s = 0.0;   // rough: the free-run time still to capture plus settling
  std::uint64_t samples = 0;  // captured in the current run
  std::uint64_t samples_expected = 0;
  std::uint64_t samples_lost = 0;  // sequence gaps + ring overruns in the current run
  double table_rate_rad_s = std::numeric_limits<double>::quiet_NaN();  // last measured, capture
};

struct RunnerOptions {
  std::string unit_serial;       // required
  std::string software_version;  // git describe of the build
  // Truth of a simulated station, recorded under "simulation" (std::nullopt on real hardware).
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
  std::function<void(int run_id, std::span<const GyroSampleRecord>)> on_samples;
  // A run as recorded (complete, rejected or aborted) with its sample count. May be empty.
  std::function<void(int run_id, const RunEnd&, std::uint64_t samples)> on_run_end;
  double progress_period_s = 0.5;
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
  nlohmann::json estimate_json;                        // as recorded in session.json (or null)
  std::vector<std::string> warnings;                   // flagged runs, estimator warnings
  int complete_runs = 0;
};

// Runs the whole sequence into the new, empty directory `dir`. The three config files are copied
// into <dir>/config/ (so `resume` needs nothing else and the record shows what was run).
SessionResult RunSession(const BenchConfigs& configs, const BenchHardware& hardware,
                         const std::filesystem::path& dir, const RunnerOptions& options);

// Continues an interrupted or failed session with the runs that are not complete, using the configs
// saved in <dir>/config/ (loaded by the caller with LoadSavedConfigs), then estimates all runs.
SessionResult ResumeSession(const BenchConfigs& configs, const BenchHardware& hardware,
                            const std::filesystem::path& dir, const RunnerOptions& options);

// The configs a session was started with (<dir>/config/{station,sequence,limits}.toml), checked
// against the SHA-256 recorded in session.json.
std::expected<BenchConfigs, std::string> LoadSavedConfigs(const std::filesystem::path& dir);

}  // namespace hrgbench::bench
