#pragma once
// StationConfig: the facts of one bench station (bench_configs/station-*.toml): which hardware it
// has (simulated in-process, or a real gyro on a CAN interface and a rate table over Modbus), where
// it stands (latitude, orientation of the table axis, for the Earth-rate part of Ω) and how the
// capture thread may be scheduled. Plain data; every key, unit and default is documented in
// bench_configs/README.md, and the in-class defaults below are the documented ones.
//
// Loading is strict (STYLE rule 10): unknown keys, wrong types, out-of-range values, missing
// required keys, bad enum strings and keys that do not apply to the station's kind are errors
// naming the file, the line, the key and the value. The loader does not touch any hardware.
//
// Not thread-safe; no real-time use (allocates). Loaders return std::expected, never throw
// (except std::bad_alloc).

#include <array>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/config/simulated_carrier.hpp"
#include "hrgbench/config/site.hpp"
#include "hrgbench/config/station_offers.hpp"
#include "hrgbench/estimator/iq_convention.hpp"
#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/physical_parameters.hpp"
#include "hrgbench/session/electronics.hpp"

namespace hrgbench::bench {

enum class StationKind { kSimulated, kReal };
std::string_view ToString(StationKind kind) noexcept;  // "simulated", "real"

enum class TableTransport { kTcp, kRtu };
std::string_view ToString(TableTransport transport) noexcept;  // "tcp", "rtu"

// [table] omega_source: which of the table's measurements gives a run's Ω (bench/run_omega.hpp).
// Absent: the angle when the table reports one (register map version 2, the simulated tables),
// the rate readings otherwise. "angle": the angle, and a run on a table without one is an ERROR.
// "rate": the rate readings' mean, as before the angle existed. Both are recorded either way.
enum class OmegaSourceSetting { kAngleWhenReported, kAngle, kRate };
// "angle when reported" (the default, not a value of the key), "angle", "rate".
std::string_view ToString(OmegaSourceSetting setting) noexcept;

// [gyro]: the gyro electronics' link. Timeouts apply to the simulated station too (its simulated
// electronics speak the same protocol on an in-process bus); the CAN interface keys only to real.
struct GyroLinkConfig {
  std::string can_interface;  // real: SocketCAN interface name ("can0", "vcan0")
  // The electronics' node id on the bus (0..15; gyro protocol v2): a station without [[fixture]].
  int can_node = 0;
  // Nominal bit rate, bit/s: real, set by `ip link` (checked); simulated, the in-process bus's
  // (1 Mbit/s). The plan's bus load is judged at it (hrg-bench check).
  std::int64_t bitrate = 1'000'000;
  bool fd = false;  // ask for the CAN FD sample stream when the interface has FD
  // FD data-phase bit rate, bit/s: real, fd only (default 2 Mbit/s); simulated, the in-process
  // bus's (5 Mbit/s, set by the loader).
  std::int64_t data_bitrate = 2'000'000;
  std::int64_t ack_timeout_ms = 50;      // per command attempt; the electronics answer in < 5 ms
  std::int64_t command_attempts = 3;     // attempts per command (a lost frame costs one retry)
  std::int64_t status_poll_ms = 20;      // status request period while waiting for "ready"
  std::int64_t sample_timeout_ms = 100;  // no sample for this long in a free run: "gyro stopped"
  // The electronics' output low-pass (output_filter, output_filter_order, output_filter_cutoff_hz):
  // the shape of the pick-off noise the fit's checks assume. Default: none (white noise).
  OutputFilter output_filter;
  // The electronics' demodulation sign convention (iq_convention = "minus-sine" | "plus-sine",
  // estimator/iq_convention.hpp): recorded as electronics.iq_convention; a "plus-sine" record is
  // conjugated into the model's before every fit.
  estimator::IqConvention iq_convention = estimator::IqConvention::kMinusSine;
  // What free runs cannot measure of the pick-off (pickoff_cross_talk_stage,
  // pickoff_coupling_bound_rad; session/electronics.hpp): recorded as electronics.pickoff.
  PickoffDeclaration pickoff;
};

// [table]: the rate table. The software limits and the acceleration apply to both kinds; the
// Modbus link keys only to kind = "real" (the simulated table is in-process, no link).
struct TableLinkConfig {
  TableTransport transport = TableTransport::kTcp;
  std::string host;                        // tcp: controller address (required)
  std::int64_t port = 502;                 // tcp
  std::string device;                      // rtu: serial device (required)
  std::int64_t baud = 115200;              // rtu
  char parity = 'N';                       // rtu: 'N', 'E', 'O'
  std::int64_t data_bits = 8;              // rtu
  std::int64_t stop_bits = 1;              // rtu
  std::int64_t unit_id = 1;                // Modbus unit id 1..247
  std::int64_t response_timeout_ms = 200;  // per transaction attempt
  std::int64_t byte_timeout_ms = 50;       // rtu: gap allowed inside one reply
  std::int64_t transaction_attempts = 2;
  std::int64_t connect_attempts = 3;
  std::int64_t reconnect_backoff_ms = 100;
  std::int64_t heartbeat_period_ms = 200;  // <= watchdog_ms / 2
  std::int64_t safe_stop_budget_ms = 1000;
  // Both kinds:
  std::int64_t watchdog_ms = 1000;  // the table stops itself without a heartbeat this long
  double max_rate_rad_s = 10.0;     // software limit: no |Ω| above it is ever commanded
  double max_accel_rad_s2 = 5.0;    // software limit on the acceleration setting
  double accel_rad_s2 = 1.0;        // acceleration limit written at connect, <= max_accel_rad_s2
  OmegaSourceSetting omega_source = OmegaSourceSetting::kAngleWhenReported;
};

// [simulated.faults]: failure injection for tests; everything off by default. Absent optionals
// mean "never".
struct SimulatedFaults {
  bool table_never_stable = false;                       // the table's rate never settles
  std::optional<double> table_fault_after_s;             // table latches a drive fault after t s
  std::optional<double> table_unresponsive_after_s;      // table stops answering after t s
  std::optional<std::int64_t> gyro_stall_after_samples;  // gyro stops streaming in a free run
  std::int64_t gyro_stall_from_run = 1;  // ... in this free run of the session and every later one
  std::optional<std::int64_t> gyro_bus_off_after_samples;  // the bus goes bus-off in a free run
  std::int64_t gyro_drop_every_nth_sample = 0;  // drop every n-th sample frame (0 = none)
  bool gyro_never_ready = false;                // excitation never reports ready
};

// [simulated] physics: where the simulated gyro's samples come from.
enum class SimulatedPhysics {
  kSlow,     // the estimator's own model (delta, xi, sigma)
  kCarrier,  // the 2-DOF resonator at its carrier and real electronics ([simulated.carrier])
};

// [simulated]: the in-process simulated station (drivers/sim physics, seeded, reproducible).
struct SimulatedStationConfig {
  // true: simulated time on a manual clock, advanced as fast as the CPU allows (CI);
  // false: paced on the wall clock at time_scale.
  bool faster_than_real_time = false;
  double time_scale = 1.0;  // simulated s per wall-clock s when paced; 1 = real time
  // The truth the simulated gyro follows (docs/estimator/model.md, "Parameters").
  estimator::Delta delta = (estimator::Delta() << -0.001, 0.3, 0.0, 0.0, 0.0, 0.0).finished();
  estimator::Xi xi = (estimator::Xi() << 0.01, 0.0, 0.0, 0.0).finished();
  double sigma = 1e-4;  // white noise std per channel of y (amplitude units); 0 = noise-free
  std::uint64_t seed = 1;
  double resonant_frequency_hz = 5000.0;
  double temperature_c = 25.0;             // resonator housing at the start
  double temperature_drift_c_per_s = 0.0;  // linear drift (tests the warm-up and drift checks)
  double excite_time_s = 0.2;              // time from Excite to "ready"
  // The forcers' errors the operating mode acts through (docs/estimator/operating-mode.md "The
  // model with the control", terms 4 and 5; every unit of the station, either physics: at carrier
  // level in the electrode frame): β1, β2, β3, β4 (gain and angle, F = I + β1·σz + β4·σx −
  // i·(β2·σz + β3·σx)) and b (the frame turned from the pick-off's, F += b·J). Free runs cannot see
  // them; the tuning's refinement does.
  std::array<double, 5> forcer_errors{};
  SimulatedPhysics physics = SimulatedPhysics::kSlow;
  SimulatedCarrierConfig carrier;  // physics = kCarrier only
  // Table physics (drivers/sim/table_physics.hpp).
  double table_settle_time_constant_s = 0.05;
  double table_noise_rad_s = 2e-5;                      // measured-rate noise, 1 σ
  std::int64_t table_encoder_counts_per_rev = 1 << 23;  // the table top's encoder resolution
  double table_encoder_noise_rad = 1e-6;  // encoder read noise, 1 σ, before quantisation
  double table_stable_tolerance_rad_s = 1e-3;
  double table_stable_hold_s = 0.2;
  SimulatedFaults faults;
};

// [realtime]: how the capture thread is scheduled. The app records what it actually got.
struct RealtimeConfig {
  int priority = 0;          // SCHED_FIFO priority 1..99; 0 = normal scheduling
  int cpu = -1;              // pin the capture thread to this CPU; -1 = any
  bool lock_memory = false;  // mlockall(MCL_CURRENT | MCL_FUTURE) before the first run
};

// [[fixture]]: one position of the table's fixture and the unit in it. A station without
// [[fixture]] has one position, "1", on [gyro] can_interface and can_node. Each unit has a bus of
// its own or shares one with other units (distinct node ids); [gyro]'s other keys apply to every
// position.
struct FixturePosition {
  std::string name;  // position = "A": 1..8 letters, digits, '-' or '_'; unique on the fixture
  // real: the unit's SocketCAN interface; simulated: the in-process bus's name, also the one its
  // candump log gives it ("vsim-<position>" by default: a bus of its own; "vcan-sim" for the one
  // position of a station without [[fixture]]). Positions naming the same interface share its bus.
  std::string can_interface;
  // The unit's node id on its bus (0..15, gyro protocol v2): distinct among the fitted positions
  // on one interface.
  int can_node = 0;
  bool fitted = true;  // false: nothing in this position today (it takes no part)
  // The unit is mounted with its sensitive axis against the table's axis (upside down): it senses
  // −Ω and the Earth rate on −axis; its record is in its own frame.
  bool inverted = false;
  std::size_t index = 0;  // in the order declared
  // kind = simulated: the keys the position sets for its unit over [simulated]'s (delta, xi, sigma,
  // seed, resonant_frequency_hz, temperature_c, temperature_drift_c_per_s, excite_time_s and
  // [fixture.faults]' gyro_* keys). PositionSimulated applies them.
  struct SimulatedKeys {
    std::optional<estimator::Delta> delta;
    std::optional<estimator::Xi> xi;
    std::optional<double> sigma;
    std::optional<std::uint64_t> seed;
    std::optional<double> resonant_frequency_hz;
    std::optional<double> temperature_c;
    std::optional<double> temperature_drift_c_per_s;
    std::optional<double> excite_time_s;
    std::optional<std::int64_t> gyro_stall_after_samples;
    std::optional<std::int64_t> gyro_stall_from_run;
    std::optional<std::int64_t> gyro_bus_off_after_samples;
    std::optional<std::int64_t> gyro_drop_every_nth_sample;
    std::optional<bool> gyro_never_ready;
  } simulated;
};

// A fixture carries at most this many positions.
inline constexpr std::size_t kMaxFixturePositions = 16;
// The highest node id a unit may have on its bus (the gyro CAN protocol's 4 bits).
inline constexpr int kMaxCanNode = 15;

struct StationConfig {
  std::filesystem::path file;  // where it was loaded from
  std::string sha256_hex;      // SHA-256 of the file's bytes (recorded in the session)

  std::string name;  // [station] name, recorded in the session (required)
  std::string description;
  StationKind kind = StationKind::kSimulated;
  SiteConfig site;  // where it stands; its Earth rate: EarthRateOnAxisRadS(site) (site.hpp)
  GyroLinkConfig gyro;
  TableLinkConfig table;
  SimulatedStationConfig simulated;      // meaningful only for kind = kSimulated
  std::vector<FixturePosition> fixture;  // at least one, in the order declared
  RealtimeConfig realtime;
  // [results] url: where hrg-bench uploads each closed session (results/results_url.hpp:
  // "sqlite:///path" or "postgresql://host/db", never a password). Empty: no upload.
  std::string results_url;
  // The file wrote a relative SQLite path ("sqlite://out/results.sqlite"): LoadStationConfig made
  // it absolute from the station file's folder (as a reader of the file expects, wherever the
  // program runs); ParseStationConfig (text, no folder) leaves it as written, from the cwd.
  bool results_url_relative = false;
  // [offers]: what the panel lists and selects first (station_offers.hpp).
  StationOffers offers;
  // [report] paper = "A4" | "Letter": the sheet of the session report's PDF, as
  // report::ParsePaperSize names it ("a4", "letter"). A4 when the station does not say;
  // hrg-report --paper overrides it.
  std::string report_paper = "a4";
};

// The fitted positions, in the order declared.
std::vector<const FixturePosition*> FittedPositions(const StationConfig& station);

// The simulated unit in `position`: [simulated] with the position's own keys. Its seed, when the
// position gives none: [simulated]'s seed + 1000 × the position's index, so that no two units
// draw the same noise (the first position's is [simulated]'s).
SimulatedStationConfig PositionSimulated(const StationConfig& station,
                                         const FixturePosition& position);

std::expected<StationConfig, config_file::ConfigError> LoadStationConfig(
    const std::filesystem::path& file);
// The same from text in memory; `file` is only used in messages.
std::expected<StationConfig, config_file::ConfigError> ParseStationConfig(
    std::string_view toml_text, const std::filesystem::path& file);

}  // namespace hrgbench::bench
