// Loader of station files. Reads table by table; each table reader reports its unknown keys last,
// so a misspelt key is reported even when everything else is right.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>

#include "hrgbench/config/config_bounds.hpp"
#include "hrgbench/config/results_url.hpp"
#include "hrgbench/config/station_config.hpp"
#include "hrgbench/config/toml_reader.hpp"
#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "station_offers_reader.hpp"

namespace hrgbench::bench {
namespace {

using namespace config_file;  // NOLINT(google-build-using-namespace): the loader's vocabulary

constexpr double kInf = std::numeric_limits<double>::infinity();
// gyro_stall_from_run: a session has at most this many runs (the sequence's bound).
constexpr auto kMaxRunsBound = static_cast<std::int64_t>(kMaxRuns);
constexpr std::string_view kRealOnly = "applies only to kind = \"real\"";
// The simulated station's in-process bus: FD data phase at 5 Mbit/s (a common FD setting).
constexpr std::int64_t kSimulatedFdDataBitRateBps = 5'000'000;

std::expected<SiteConfig, ConfigError> ReadSite(TableReader& reader) {
  SiteConfig site;
  HRG_TRY(latitude, RequiredNumber(reader, "latitude_deg", {-90.0, 90.0, true, "in [-90, 90]"}));
  site.latitude_deg = *latitude;

  const toml::node* enu = reader.Find("axis_enu");
  const toml::node* elevation = reader.Find("axis_elevation_deg");
  const toml::node* azimuth = reader.Find("axis_azimuth_deg");
  if (enu != nullptr && (elevation != nullptr || azimuth != nullptr)) {
    return std::unexpected(reader.Error(
        *enu, "axis_enu",
        "conflict: give the axis either as axis_enu or as axis_elevation_deg/axis_azimuth_deg"));
  }
  if (enu != nullptr) {
    HRG_TRY(v, VectorFrom<3>(reader, *enu, "axis_enu", kAnyFinite));
    const double norm = v->norm();
    // A unit vector written with 4-5 digits is within 1e-3 of length 1; anything further off is a
    // mistyped component, not rounding.
    if (std::abs(norm - 1.0) > 1e-3) {
      return std::unexpected(reader.Error(*enu, "axis_enu",
                                          "out of range: must be a unit vector (east, north, up), "
                                          "|v| within 1e-3 of 1, got |v| = " +
                                              std::to_string(norm)));
    }
    site.axis_enu = {(*v)(0) / norm, (*v)(1) / norm, (*v)(2) / norm};
  } else if (elevation != nullptr || azimuth != nullptr) {
    if (elevation == nullptr)
      return std::unexpected(reader.Missing("axis_elevation_deg", "a number in [-90, 90]"));
    if (azimuth == nullptr)
      return std::unexpected(reader.Missing("axis_azimuth_deg", "a number in [0, 360)"));
    HRG_TRY(el, NumberFrom(reader, *elevation, "axis_elevation_deg",
                           {-90.0, 90.0, true, "in [-90, 90]"}));
    HRG_TRY(az, NumberFrom(reader, *azimuth, "axis_azimuth_deg",
                           {0.0, 360.0, true, "in [0, 360)", false}));
    site.axis_enu = AxisFromElevationAzimuth(*el, *az);
  }
  HRG_CHECK(reader.Unknown("latitude_deg, axis_enu, axis_elevation_deg, axis_azimuth_deg"));
  return site;
}

// can_interface: a Linux interface name (IFNAMSIZ is 16 including the terminating zero).
std::expected<std::string, ConfigError> ReadInterfaceName(TableReader& reader) {
  HRG_TRY(iface, RequiredString(reader, "can_interface"));
  if (iface->size() > 15) {
    return std::unexpected(reader.Error(*reader.table().get("can_interface"), "can_interface",
                                        "out of range: a Linux interface name has <= 15 "
                                        "characters"));
  }
  return *iface;
}

// `fixture_declared`: the station has [[fixture]], whose positions name the interfaces.
std::expected<GyroLinkConfig, ConfigError> ReadGyro(TableReader& reader, StationKind kind,
                                                    bool fixture_declared) {
  GyroLinkConfig gyro;
  HRG_TRY(fd, OptionalBool(reader, "fd", gyro.fd));
  gyro.fd = *fd;
  if (kind == StationKind::kReal) {
    if (fixture_declared) {
      HRG_CHECK(Forbid(reader, "can_interface",
                       "conflict: with [[fixture]], each position names its own can_interface"));
    } else {
      HRG_TRY(iface, ReadInterfaceName(reader));
      gyro.can_interface = *iface;
    }
    if (fixture_declared) {
      HRG_CHECK(Forbid(reader, "can_node",
                       "conflict: with [[fixture]], each position names its own can_node"));
    } else {
      HRG_TRY(node, OptionalInteger(reader, "can_node", 0, kMaxCanNode, gyro.can_node));
      gyro.can_node = static_cast<int>(*node);
    }
    HRG_TRY(bitrate, OptionalInteger(reader, "bitrate", 10'000, 1'000'000, gyro.bitrate));
    gyro.bitrate = *bitrate;
    if (gyro.fd) {
      HRG_TRY(data, OptionalInteger(reader, "data_bitrate", 10'000, 8'000'000, gyro.data_bitrate));
      gyro.data_bitrate = *data;
      if (gyro.data_bitrate < gyro.bitrate) {
        return std::unexpected(reader.Error(
            *reader.table().get("data_bitrate"), "data_bitrate",
            "out of range: must be >= bitrate (" + std::to_string(gyro.bitrate) + ")"));
      }
    } else {
      HRG_CHECK(Forbid(reader, "data_bitrate", "applies only with fd = true"));
    }
  } else {
    for (std::string_view key : {"can_interface", "can_node", "bitrate", "data_bitrate"})
      HRG_CHECK(Forbid(reader, key, kRealOnly));
    gyro.data_bitrate = kSimulatedFdDataBitRateBps;
  }
  HRG_TRY(ack, OptionalInteger(reader, "ack_timeout_ms", 1, 10'000, gyro.ack_timeout_ms));
  gyro.ack_timeout_ms = *ack;
  HRG_TRY(attempts, OptionalInteger(reader, "command_attempts", 1, 10, gyro.command_attempts));
  gyro.command_attempts = *attempts;
  HRG_TRY(poll, OptionalInteger(reader, "status_poll_ms", 1, 10'000, gyro.status_poll_ms));
  gyro.status_poll_ms = *poll;
  HRG_TRY(sample, OptionalInteger(reader, "sample_timeout_ms", 1, 60'000, gyro.sample_timeout_ms));
  gyro.sample_timeout_ms = *sample;
  // The electronics' output low-pass: what colours the pick-off noise (session/electronics.hpp).
  HRG_TRY(filter, Choice(reader, "output_filter", {"none", "butterworth"}, 0));
  if (*filter == 1) {
    gyro.output_filter.kind = OutputFilterKind::kButterworth;
    HRG_TRY(order, OptionalInteger(reader, "output_filter_order", 1,
                                   estimator::kMaxButterworthOrder, gyro.output_filter.order));
    gyro.output_filter.order = *order;
    HRG_TRY(cutoff, OptionalNumber(reader, "output_filter_cutoff_hz",
                                   {0.0, 1e6, false, "in (0, 1e6]"}, gyro.output_filter.cutoff_hz));
    gyro.output_filter.cutoff_hz = *cutoff;
  } else {
    for (std::string_view key : {"output_filter_order", "output_filter_cutoff_hz"})
      HRG_CHECK(Forbid(reader, key, "applies only with output_filter = \"butterworth\""));
  }
  // Which way the electronics' quadrature channels point (estimator/iq_convention.hpp).
  HRG_TRY(iq, Choice(reader, "iq_convention", {"minus-sine", "plus-sine"},
                     gyro.iq_convention == estimator::IqConvention::kPlusSine ? 1 : 0));
  gyro.iq_convention =
      *iq == 1 ? estimator::IqConvention::kPlusSine : estimator::IqConvention::kMinusSine;
  // What free runs cannot measure of the pick-off (session/electronics.hpp).
  HRG_TRY(stage,
          Choice(reader, "pickoff_cross_talk_stage", {"midway", "before_gain", "after_gain"}, 0));
  gyro.pickoff.cross_talk_stage = *stage == 1   ? estimator::CrossTalkStage::kBeforeGain
                                  : *stage == 2 ? estimator::CrossTalkStage::kAfterGain
                                                : estimator::CrossTalkStage::kMidway;
  HRG_TRY(bound, OptionalNumber(reader, "pickoff_coupling_bound_rad",
                                {0.0, kMaxCouplingBoundRad, true, "in [0, 0.1]"},
                                gyro.pickoff.unmodelled_coupling_bound_rad));
  gyro.pickoff.unmodelled_coupling_bound_rad = *bound;
  HRG_CHECK(
      reader.Unknown("can_interface, can_node, bitrate, fd, data_bitrate, ack_timeout_ms, "
                     "command_attempts, "
                     "status_poll_ms, sample_timeout_ms, output_filter, output_filter_order, "
                     "output_filter_cutoff_hz, iq_convention, pickoff_cross_talk_stage, "
                     "pickoff_coupling_bound_rad"));
  return gyro;
}

std::expected<void, ConfigError> ReadTableLink(TableReader& reader, TableLinkConfig& table) {
  HRG_TRY(transport, Choice(reader, "transport", {"tcp", "rtu"}, -1));
  table.transport = *transport == 0 ? TableTransport::kTcp : TableTransport::kRtu;
  if (table.transport == TableTransport::kTcp) {
    HRG_TRY(host, RequiredString(reader, "host"));
    table.host = *host;
    HRG_TRY(port, OptionalInteger(reader, "port", 1, 65535, table.port));
    table.port = *port;
    for (std::string_view key :
         {"device", "baud", "parity", "data_bits", "stop_bits", "byte_timeout_ms"}) {
      HRG_CHECK(Forbid(reader, key, "applies only to transport = \"rtu\""));
    }
  } else {
    HRG_TRY(device, RequiredString(reader, "device"));
    table.device = *device;
    HRG_TRY(baud, OptionalInteger(reader, "baud", 300, 4'000'000, table.baud));
    table.baud = *baud;
    HRG_TRY(parity, Choice(reader, "parity", {"N", "E", "O"}, 0));
    table.parity = "NEO"[*parity];
    HRG_TRY(data_bits, OptionalInteger(reader, "data_bits", 5, 8, table.data_bits));
    table.data_bits = *data_bits;
    HRG_TRY(stop_bits, OptionalInteger(reader, "stop_bits", 1, 2, table.stop_bits));
    table.stop_bits = *stop_bits;
    HRG_TRY(byte_timeout,
            OptionalInteger(reader, "byte_timeout_ms", 1, 60'000, table.byte_timeout_ms));
    table.byte_timeout_ms = *byte_timeout;
    for (std::string_view key : {"host", "port"})
      HRG_CHECK(Forbid(reader, key, "applies only to transport = \"tcp\""));
  }
  HRG_TRY(unit, OptionalInteger(reader, "unit_id", 1, 247, table.unit_id));
  table.unit_id = *unit;
  HRG_TRY(response,
          OptionalInteger(reader, "response_timeout_ms", 1, 60'000, table.response_timeout_ms));
  table.response_timeout_ms = *response;
  HRG_TRY(transactions,
          OptionalInteger(reader, "transaction_attempts", 1, 10, table.transaction_attempts));
  table.transaction_attempts = *transactions;
  HRG_TRY(connects, OptionalInteger(reader, "connect_attempts", 1, 10, table.connect_attempts));
  table.connect_attempts = *connects;
  HRG_TRY(backoff,
          OptionalInteger(reader, "reconnect_backoff_ms", 0, 10'000, table.reconnect_backoff_ms));
  table.reconnect_backoff_ms = *backoff;
  HRG_TRY(heartbeat,
          OptionalInteger(reader, "heartbeat_period_ms", 1, 30'000, table.heartbeat_period_ms));
  table.heartbeat_period_ms = *heartbeat;
  HRG_TRY(budget,
          OptionalInteger(reader, "safe_stop_budget_ms", 1, 60'000, table.safe_stop_budget_ms));
  table.safe_stop_budget_ms = *budget;
  return {};
}

std::expected<TableLinkConfig, ConfigError> ReadTable(TableReader& reader, StationKind kind) {
  TableLinkConfig table;
  if (kind == StationKind::kReal) {
    if (auto ok = ReadTableLink(reader, table); !ok) return std::unexpected(ok.error());
  } else {
    for (std::string_view key :
         {"transport", "host", "port", "device", "baud", "parity", "data_bits", "stop_bits",
          "unit_id", "response_timeout_ms", "byte_timeout_ms", "transaction_attempts",
          "connect_attempts", "reconnect_backoff_ms", "heartbeat_period_ms",
          "safe_stop_budget_ms"}) {
      HRG_CHECK(Forbid(reader, key, kRealOnly));
    }
  }
  // The register map's watchdog range (the Modbus rate-table driver's register_map.hpp).
  HRG_TRY(watchdog, OptionalInteger(reader, "watchdog_ms", 100, 60'000, table.watchdog_ms));
  table.watchdog_ms = *watchdog;
  if (kind == StationKind::kReal && table.heartbeat_period_ms > table.watchdog_ms / 2) {
    const toml::node* node = reader.table().get("heartbeat_period_ms");
    const std::string message = "out of range: must be <= watchdog_ms / 2 (" +
                                std::to_string(table.watchdog_ms / 2) +
                                ") so that one lost heartbeat does not stop the table";
    if (node == nullptr) return std::unexpected(reader.Missing("heartbeat_period_ms", message));
    return std::unexpected(reader.Error(*node, "heartbeat_period_ms", message));
  }
  HRG_TRY(max_rate, OptionalNumber(reader, "max_rate_rad_s", {0.0, 100.0, false, "in (0, 100]"},
                                   table.max_rate_rad_s));
  table.max_rate_rad_s = *max_rate;
  HRG_TRY(max_accel, OptionalNumber(reader, "max_accel_rad_s2",
                                    {0.0, 1000.0, false, "in (0, 1000]"}, table.max_accel_rad_s2));
  table.max_accel_rad_s2 = *max_accel;
  HRG_TRY(accel, OptionalNumber(reader, "accel_rad_s2", kPositive, table.accel_rad_s2));
  table.accel_rad_s2 = *accel;
  if (table.accel_rad_s2 > table.max_accel_rad_s2) {
    const toml::node* node = reader.table().get("accel_rad_s2");
    const std::string message = "out of range: must be <= max_accel_rad_s2 (" +
                                std::to_string(table.max_accel_rad_s2) + ")";
    if (node == nullptr) return std::unexpected(reader.Missing("accel_rad_s2", message));
    return std::unexpected(reader.Error(*node, "accel_rad_s2", message));
  }
  // Absent is its own setting (the angle when the table reports one), not one of the values.
  if (reader.table().get("omega_source") != nullptr) {
    HRG_TRY(source, Choice(reader, "omega_source", {"angle", "rate"}, -1));
    table.omega_source = *source == 0 ? OmegaSourceSetting::kAngle : OmegaSourceSetting::kRate;
  } else {
    reader.Find("omega_source");
  }
  HRG_CHECK(reader.Unknown(
      "transport, host, port, device, baud, parity, data_bits, stop_bits, unit_id, "
      "response_timeout_ms, byte_timeout_ms, transaction_attempts, connect_attempts, "
      "reconnect_backoff_ms, heartbeat_period_ms, safe_stop_budget_ms, watchdog_ms, "
      "max_rate_rad_s, max_accel_rad_s2, accel_rad_s2, omega_source"));
  return table;
}

// [simulated.faults], or (`unit_only`) a position's [fixture.faults]: the gyro_* keys only.
std::expected<SimulatedFaults, ConfigError> ReadFaults(TableReader& reader, bool unit_only) {
  SimulatedFaults faults;
  constexpr std::int64_t kMaxCount = std::numeric_limits<std::int64_t>::max();
  if (unit_only) {
    for (std::string_view key :
         {"table_never_stable", "table_fault_after_s", "table_unresponsive_after_s"})
      HRG_CHECK(Forbid(reader, key, "a table's fault belongs in [simulated.faults]"));
  } else {
    HRG_TRY(never_stable, OptionalBool(reader, "table_never_stable", false));
    faults.table_never_stable = *never_stable;
    // Absent means never; a time beyond any session is a typo, not a way to say never.
    constexpr Range kFaultTime{0.0, kMaxLongWaitS, true, "in [0, 86400] s (a day)"};
    HRG_TRY(fault_after, MaybeNumber(reader, "table_fault_after_s", kFaultTime));
    faults.table_fault_after_s = *fault_after;
    HRG_TRY(silent_after, MaybeNumber(reader, "table_unresponsive_after_s", kFaultTime));
    faults.table_unresponsive_after_s = *silent_after;
  }
  HRG_TRY(stall, MaybeInteger(reader, "gyro_stall_after_samples", 0, kMaxCount));
  faults.gyro_stall_after_samples = *stall;
  HRG_TRY(stall_run, OptionalInteger(reader, "gyro_stall_from_run", 1, kMaxRunsBound, 1));
  faults.gyro_stall_from_run = *stall_run;
  HRG_TRY(bus_off, MaybeInteger(reader, "gyro_bus_off_after_samples", 0, kMaxCount));
  faults.gyro_bus_off_after_samples = *bus_off;
  HRG_TRY(drop, OptionalInteger(reader, "gyro_drop_every_nth_sample", 0, kMaxCount, 0));
  if (*drop == 1) {
    return std::unexpected(reader.Error(*reader.table().get("gyro_drop_every_nth_sample"),
                                        "gyro_drop_every_nth_sample",
                                        "out of range: 1 would drop every sample; use 0 (off) or "
                                        ">= 2"));
  }
  faults.gyro_drop_every_nth_sample = *drop;
  HRG_TRY(never_ready, OptionalBool(reader, "gyro_never_ready", false));
  faults.gyro_never_ready = *never_ready;
  constexpr std::string_view kGyroKeys =
      "gyro_stall_after_samples, gyro_stall_from_run, gyro_bus_off_after_samples, "
      "gyro_drop_every_nth_sample, gyro_never_ready";
  HRG_CHECK(reader.Unknown(
      unit_only ? std::string(kGyroKeys)
                : "table_never_stable, table_fault_after_s, table_unresponsive_after_s, " +
                      std::string(kGyroKeys)));
  return faults;
}

// HRG_TRY for a function that returns std::optional<ConfigError>.
#define HRG_UNIT_TRY(var, expr) \
  auto var = (expr);            \
  if (!var) return std::move(var).error()

// The keys that describe one simulated unit (its truth and behaviour), read into `sim` over the
// values it has: [simulated]'s, or a position's over the station's. Physics as sim.physics says.
std::optional<ConfigError> ReadSimulatedUnit(TableReader& reader, SimulatedStationConfig& sim,
                                             std::int64_t default_seed) {
  const bool carrier = sim.physics == SimulatedPhysics::kCarrier;
  if (!carrier && reader.table().get("delta") != nullptr) {
    HRG_UNIT_TRY(delta, RequiredVector<6>(reader, "delta", kAnyFinite));
    sim.delta = *delta;
  } else if (!carrier) {
    reader.Find("delta");
  }
  if (!carrier && reader.table().get("xi") != nullptr) {
    // Each |ξi| < 1/4 keeps I + C(ξ) invertible (estimator/model.hpp).
    HRG_UNIT_TRY(xi, RequiredVector<4>(reader, "xi",
                                       {-0.25, 0.25, false,
                                        "in (-0.25, 0.25) so that I + C(xi) is "
                                        "invertible",
                                        false}));
    sim.xi = *xi;
  } else if (!carrier) {
    reader.Find("xi");
  }
  if (!carrier) {
    HRG_UNIT_TRY(sigma, OptionalNumber(reader, "sigma", {0.0, 1.0, true, "in [0, 1]"}, sim.sigma));
    sim.sigma = *sigma;
  }
  HRG_UNIT_TRY(seed, OptionalInteger(reader, "seed", 0, std::numeric_limits<std::int64_t>::max(),
                                     default_seed));
  sim.seed = static_cast<std::uint64_t>(*seed);
  // The electronics report it in a 24-bit mHz field: the simulated ones refuse more.
  if (!carrier) {
    HRG_UNIT_TRY(
        f, OptionalNumber(reader, "resonant_frequency_hz",
                          {0.0, hw::kMaxReportedResonantFrequencyHz, false, "in (0, 16777.215]"},
                          sim.resonant_frequency_hz));
    sim.resonant_frequency_hz = *f;
  }
  HRG_UNIT_TRY(t, OptionalNumber(reader, "temperature_c", {-60.0, 150.0, true, "in [-60, 150]"},
                                 sim.temperature_c));
  sim.temperature_c = *t;
  HRG_UNIT_TRY(drift,
               OptionalNumber(reader, "temperature_drift_c_per_s", {-1.0, 1.0, true, "in [-1, 1]"},
                              sim.temperature_drift_c_per_s));
  sim.temperature_drift_c_per_s = *drift;
  HRG_UNIT_TRY(excite, OptionalNumber(reader, "excite_time_s", {0.0, 600.0, true, "in [0, 600]"},
                                      sim.excite_time_s));
  sim.excite_time_s = *excite;
  return std::nullopt;
}

std::expected<SimulatedStationConfig, ConfigError> ReadSimulated(TableReader& reader) {
  SimulatedStationConfig sim;
  HRG_TRY(fast, OptionalBool(reader, "faster_than_real_time", sim.faster_than_real_time));
  sim.faster_than_real_time = *fast;
  if (sim.faster_than_real_time) {
    HRG_CHECK(Forbid(reader, "time_scale",
                     "applies only with faster_than_real_time = false (a manual clock has no "
                     "pace)"));
  } else {
    HRG_TRY(scale, OptionalNumber(reader, "time_scale", {0.01, 1000.0, true, "in [0.01, 1000]"},
                                  sim.time_scale));
    sim.time_scale = *scale;
  }
  HRG_TRY(physics, Choice(reader, "physics", {"slow", "carrier"}, 0));
  sim.physics = *physics == 0 ? SimulatedPhysics::kSlow : SimulatedPhysics::kCarrier;
  const bool carrier = sim.physics == SimulatedPhysics::kCarrier;
  if (carrier) {
    // The carrier physics takes its truth, noise and frequency from [simulated.carrier].
    for (std::string_view key : {"delta", "xi", "sigma", "resonant_frequency_hz"}) {
      HRG_CHECK(Forbid(reader, key,
                       "applies only to physics = \"slow\" (physics = \"carrier\" takes it "
                       "from [simulated.carrier])"));
    }
    HRG_TRY(carrier_table, SubTable(reader, "carrier", false));
    if (*carrier_table != nullptr) {
      TableReader carrier_reader(**carrier_table, reader.KeyPath("carrier"), reader.source());
      HRG_TRY(carrier_config, ReadSimulatedCarrier(carrier_reader));
      sim.carrier = *carrier_config;
    }
  } else {
    HRG_CHECK(
        Forbid(reader, "carrier", "[simulated.carrier] applies only to physics = \"carrier\""));
  }
  HRG_CHECK(ReadSimulatedUnit(reader, sim, 1));
  if (reader.table().get("forcer_errors") != nullptr) {
    // 0.1 is a forcer 10 % off or turned 6°: far beyond any trimmed electronics.
    HRG_TRY(forcer,
            RequiredVector<5>(reader, "forcer_errors", {-0.1, 0.1, true, "in [-0.1, 0.1]"}));
    for (int i = 0; i < 5; ++i) sim.forcer_errors[static_cast<std::size_t>(i)] = (*forcer)(i);
  }
  HRG_TRY(tau, OptionalNumber(reader, "table_settle_time_constant_s",
                              {0.0, 60.0, false, "in (0, 60]"}, sim.table_settle_time_constant_s));
  sim.table_settle_time_constant_s = *tau;
  HRG_TRY(noise, OptionalNumber(reader, "table_noise_rad_s", {0.0, 1.0, true, "in [0, 1]"},
                                sim.table_noise_rad_s));
  sim.table_noise_rad_s = *noise;
  // The encoder: from 2^12 counts/rev (a coarse motor encoder) to 2^31 (the count's signed
  // difference must hold one revolution); read noise up to 1e-3 rad (3 arcmin).
  HRG_TRY(counts, OptionalInteger(reader, "table_encoder_counts_per_rev", 1 << 12,
                                  std::int64_t{1} << 31, sim.table_encoder_counts_per_rev));
  sim.table_encoder_counts_per_rev = *counts;
  HRG_TRY(encoder_noise,
          OptionalNumber(reader, "table_encoder_noise_rad", {0.0, 1e-3, true, "in [0, 1e-3]"},
                         sim.table_encoder_noise_rad));
  sim.table_encoder_noise_rad = *encoder_noise;
  HRG_TRY(tolerance, OptionalNumber(reader, "table_stable_tolerance_rad_s", kPositive,
                                    sim.table_stable_tolerance_rad_s));
  sim.table_stable_tolerance_rad_s = *tolerance;
  HRG_TRY(hold, OptionalNumber(reader, "table_stable_hold_s", {0.0, 600.0, true, "in [0, 600]"},
                               sim.table_stable_hold_s));
  sim.table_stable_hold_s = *hold;
  HRG_TRY(faults_table, SubTable(reader, "faults", false));
  if (*faults_table != nullptr) {
    TableReader faults_reader(**faults_table, reader.KeyPath("faults"), reader.source());
    HRG_TRY(faults, ReadFaults(faults_reader, false));
    sim.faults = *faults;
  }
  HRG_CHECK(reader.Unknown(
      "faster_than_real_time, time_scale, physics, delta, xi, sigma, seed, resonant_frequency_hz, "
      "forcer_errors, temperature_c, temperature_drift_c_per_s, excite_time_s, "
      "table_settle_time_constant_s, "
      "table_noise_rad_s, table_encoder_counts_per_rev, table_encoder_noise_rad, "
      "table_stable_tolerance_rad_s, table_stable_hold_s, [simulated.carrier], "
      "[simulated.faults]"));
  return sim;
}

bool IsPositionName(std::string_view name) {
  if (name.empty() || name.size() > 8) return false;
  for (char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '-' || c == '_';
    if (!ok) return false;
  }
  return true;
}

std::expected<FixturePosition, ConfigError> ReadPosition(TableReader& reader,
                                                         const StationConfig& station,
                                                         std::size_t index) {
  FixturePosition position;
  position.index = index;
  HRG_TRY(name, RequiredString(reader, "position"));
  if (!IsPositionName(*name)) {
    return std::unexpected(reader.Error(*reader.table().get("position"), "position",
                                        "out of range: 1 to 8 letters, digits, '-' or '_' (it "
                                        "names the unit's session folder)"));
  }
  position.name = *name;
  HRG_TRY(fitted, OptionalBool(reader, "fitted", true));
  position.fitted = *fitted;
  HRG_TRY(inverted, OptionalBool(reader, "inverted", false));
  position.inverted = *inverted;
  HRG_TRY(node, OptionalInteger(reader, "can_node", 0, kMaxCanNode, 0));
  position.can_node = static_cast<int>(*node);
  if (station.kind == StationKind::kReal) {
    HRG_TRY(iface, ReadInterfaceName(reader));
    position.can_interface = *iface;
    for (std::string_view key :
         {"delta", "xi", "sigma", "seed", "resonant_frequency_hz", "temperature_c",
          "temperature_drift_c_per_s", "excite_time_s", "faults"})
      HRG_CHECK(Forbid(reader, key, "applies only to kind = \"simulated\""));
  } else {
    // The in-process bus's name: positions naming the same one share it.
    position.can_interface = "vsim-" + position.name;
    if (reader.table().contains("can_interface")) {
      HRG_TRY(iface, ReadInterfaceName(reader));
      position.can_interface = *iface;
    }
    if (station.simulated.physics == SimulatedPhysics::kCarrier) {
      for (std::string_view key : {"delta", "xi", "sigma", "resonant_frequency_hz"})
        HRG_CHECK(Forbid(reader, key,
                         "applies only to physics = \"slow\" (a carrier unit's truth is "
                         "[simulated.carrier])"));
    }
    // Read (and checked) as a whole unit; what the position itself sets is kept.
    SimulatedStationConfig unit = station.simulated;
    HRG_CHECK(ReadSimulatedUnit(reader, unit, 0));
    const toml::table& keys = reader.table();
    FixturePosition::SimulatedKeys& own = position.simulated;
    if (keys.contains("delta")) own.delta = unit.delta;
    if (keys.contains("xi")) own.xi = unit.xi;
    if (keys.contains("sigma")) own.sigma = unit.sigma;
    if (keys.contains("seed")) own.seed = unit.seed;
    if (keys.contains("resonant_frequency_hz"))
      own.resonant_frequency_hz = unit.resonant_frequency_hz;
    if (keys.contains("temperature_c")) own.temperature_c = unit.temperature_c;
    if (keys.contains("temperature_drift_c_per_s"))
      own.temperature_drift_c_per_s = unit.temperature_drift_c_per_s;
    if (keys.contains("excite_time_s")) own.excite_time_s = unit.excite_time_s;
    HRG_TRY(faults_table, SubTable(reader, "faults", false));
    if (*faults_table != nullptr) {
      TableReader faults_reader(**faults_table, reader.KeyPath("faults"), reader.source());
      HRG_TRY(faults, ReadFaults(faults_reader, true));
      const toml::table& fault_keys = faults_reader.table();
      if (fault_keys.contains("gyro_stall_after_samples"))
        own.gyro_stall_after_samples = faults->gyro_stall_after_samples;
      if (fault_keys.contains("gyro_stall_from_run"))
        own.gyro_stall_from_run = faults->gyro_stall_from_run;
      if (fault_keys.contains("gyro_bus_off_after_samples"))
        own.gyro_bus_off_after_samples = faults->gyro_bus_off_after_samples;
      if (fault_keys.contains("gyro_drop_every_nth_sample"))
        own.gyro_drop_every_nth_sample = faults->gyro_drop_every_nth_sample;
      if (fault_keys.contains("gyro_never_ready")) own.gyro_never_ready = faults->gyro_never_ready;
    }
  }
  HRG_CHECK(
      reader.Unknown("position, fitted, inverted, can_interface, can_node, delta, xi, sigma, seed, "
                     "resonant_frequency_hz, "
                     "temperature_c, temperature_drift_c_per_s, excite_time_s, [fixture.faults]"));
  return position;
}

// [[fixture]] (absent: one position on [gyro]'s interface and node). Names unique; fitted
// positions on one bus have distinct node ids (the bus load of each bus is judged by the plan
// check, hrg-bench check).
std::expected<std::vector<FixturePosition>, ConfigError> ReadFixture(TableReader& root,
                                                                     const StationConfig& station,
                                                                     const Source& source) {
  std::vector<FixturePosition> fixture;
  const toml::node* node = root.Find("fixture");
  if (node == nullptr) {
    FixturePosition only;
    only.name = "1";
    only.can_interface =
        station.kind == StationKind::kReal ? station.gyro.can_interface : "vcan-sim";
    only.can_node = station.gyro.can_node;
    fixture.push_back(std::move(only));
    return fixture;
  }
  const toml::array* positions = node->as_array();
  if (positions == nullptr || !positions->is_array_of_tables() || positions->empty()) {
    return std::unexpected(root.Error(
        *node, "fixture", "wrong type: expected one or more [[fixture]] tables, one per position"));
  }
  if (positions->size() > kMaxFixturePositions) {
    return std::unexpected(ConfigError{source.file(), LineOf(*positions->get(0)), "fixture", "",
                                       "out of range: " + std::to_string(positions->size()) +
                                           " [[fixture]] positions; a fixture has at most " +
                                           std::to_string(kMaxFixturePositions)});
  }
  for (std::size_t i = 0; i < positions->size(); ++i) {
    const toml::table& table = *positions->get(i)->as_table();
    TableReader reader(table, "fixture[" + std::to_string(i) + "]", source);
    HRG_TRY(position, ReadPosition(reader, station, i));
    for (const FixturePosition& earlier : fixture) {
      if (earlier.name == position->name) {
        return std::unexpected(
            reader.Error(*table.get("position"), "position",
                         "conflict: position '" + position->name + "' is declared twice"));
      }
      if (earlier.fitted && position->fitted && earlier.can_interface == position->can_interface &&
          earlier.can_node == position->can_node) {
        const toml::node* at = table.get("can_node");
        if (at == nullptr) at = table.get("can_interface");
        if (at == nullptr) at = table.get("position");
        return std::unexpected(reader.Error(
            *at, "can_node",
            "conflict: positions '" + earlier.name + "' and '" + position->name +
                "' are both node " + std::to_string(position->can_node) + " on " +
                position->can_interface +
                "; units on one bus need distinct can_node ids (set in each unit's electronics)"));
      }
    }
    fixture.push_back(std::move(*position));
  }
  if (std::none_of(fixture.begin(), fixture.end(),
                   [](const FixturePosition& position) { return position.fitted; })) {
    return std::unexpected(root.Error(
        *node, "fixture", "out of range: no position is fitted (fitted = false on all)"));
  }
  return fixture;
}

std::expected<RealtimeConfig, ConfigError> ReadRealtime(TableReader& reader) {
  RealtimeConfig rt;
  HRG_TRY(priority, OptionalInteger(reader, "priority", 0, 99, rt.priority));
  rt.priority = static_cast<int>(*priority);
  // CPU_SETSIZE is 1024; whether the CPU exists is checked when the thread is pinned.
  HRG_TRY(cpu, OptionalInteger(reader, "cpu", -1, 1023, rt.cpu));
  rt.cpu = static_cast<int>(*cpu);
  HRG_TRY(lock, OptionalBool(reader, "lock_memory", rt.lock_memory));
  rt.lock_memory = *lock;
  HRG_CHECK(reader.Unknown("priority, cpu, lock_memory"));
  return rt;
}

std::expected<StationConfig, ConfigError> ReadStation(const TomlDocument& document,
                                                      const std::filesystem::path& file) {
  const Source source(file, document.text);
  StationConfig station;
  station.file = file;
  station.sha256_hex = document.sha256_hex;
  TableReader root(document.root, "", source);

  HRG_TRY(station_table, SubTable(root, "station", true));
  {
    TableReader reader(**station_table, "station", source);
    HRG_TRY(name, RequiredString(reader, "name"));
    station.name = *name;
    HRG_TRY(description,
            OptionalString(reader, "description", "", false, StringKind::kDescription));
    station.description = *description;
    HRG_TRY(kind, Choice(reader, "kind", {"simulated", "real"}, -1));
    station.kind = *kind == 0 ? StationKind::kSimulated : StationKind::kReal;
    HRG_CHECK(reader.Unknown("name, description, kind"));
  }
  const bool real = station.kind == StationKind::kReal;

  HRG_TRY(site_table, SubTable(root, "site", true));
  {
    TableReader reader(**site_table, "site", source);
    HRG_TRY(site, ReadSite(reader));
    station.site = *site;
  }

  HRG_TRY(gyro_table, SubTable(root, "gyro", real));
  if (*gyro_table != nullptr) {
    TableReader reader(**gyro_table, "gyro", source);
    HRG_TRY(gyro, ReadGyro(reader, station.kind, root.table().get("fixture") != nullptr));
    station.gyro = *gyro;
  }

  HRG_TRY(table_table, SubTable(root, "table", real));
  if (*table_table != nullptr) {
    TableReader reader(**table_table, "table", source);
    HRG_TRY(table, ReadTable(reader, station.kind));
    station.table = *table;
  }

  if (real) {
    HRG_CHECK(Forbid(root, "simulated", "[simulated] applies only to kind = \"simulated\""));
  } else {
    HRG_TRY(sim_table, SubTable(root, "simulated", true));
    TableReader reader(**sim_table, "simulated", source);
    HRG_TRY(sim, ReadSimulated(reader));
    station.simulated = *sim;
  }

  HRG_TRY(fixture, ReadFixture(root, station, source));
  station.fixture = std::move(*fixture);

  HRG_TRY(rt_table, SubTable(root, "realtime", false));
  if (*rt_table != nullptr) {
    TableReader reader(**rt_table, "realtime", source);
    HRG_TRY(rt, ReadRealtime(reader));
    station.realtime = *rt;
  }

  HRG_TRY(results_table, SubTable(root, "results", false));
  if (*results_table != nullptr) {
    TableReader reader(**results_table, "results", source);
    HRG_TRY(url, RequiredString(reader, "url"));
    if (auto parsed = results::ParseResultsUrl(*url); !parsed) {
      ConfigError error = reader.Error(*reader.table().get("url"), "url", parsed.error());
      // Never echo a password into a log: the message says what is wrong without the value.
      if (parsed.error().find("password") != std::string::npos) error.value = "(not shown)";
      return std::unexpected(std::move(error));
    }
    station.results_url = *url;
    HRG_CHECK(reader.Unknown("url"));
  }

  HRG_TRY(report_table, SubTable(root, "report", false));
  if (*report_table != nullptr) {
    TableReader reader(**report_table, "report", source);
    HRG_TRY(paper, RequiredString(reader, "paper"));
    // Spelled as a sheet is named; a near miss ("a4", "US Letter") is an error, not a guess.
    if (*paper == "A4") {
      station.report_paper = "a4";
    } else if (*paper == "Letter") {
      station.report_paper = "letter";
    } else {
      return std::unexpected(
          reader.Error(*reader.table().get("paper"), "paper", "must be \"A4\" or \"Letter\""));
    }
    HRG_CHECK(reader.Unknown("paper"));
  }

  HRG_TRY(offers_table, SubTable(root, "offers", false));
  if (*offers_table != nullptr) {
    TableReader reader(**offers_table, "offers", source);
    HRG_TRY(offers, internal::ReadOffers(reader, station.kind));
    station.offers = std::move(*offers);
  }

  HRG_CHECK(
      root.Unknown("[station], [site], [gyro], [table], [simulated], [[fixture]], [realtime], "
                   "[results], [report], [offers]"));
  return station;
}

}  // namespace

std::vector<const FixturePosition*> FittedPositions(const StationConfig& station) {
  std::vector<const FixturePosition*> fitted;
  for (const FixturePosition& position : station.fixture) {
    if (position.fitted) fitted.push_back(&position);
  }
  return fitted;
}

SimulatedStationConfig PositionSimulated(const StationConfig& station,
                                         const FixturePosition& position) {
  SimulatedStationConfig unit = station.simulated;
  const FixturePosition::SimulatedKeys& own = position.simulated;
  constexpr std::uint64_t kSeedStride = 1000;
  unit.seed = own.seed.value_or(station.simulated.seed + kSeedStride * position.index);
  if (own.delta) unit.delta = *own.delta;
  if (own.xi) unit.xi = *own.xi;
  if (own.sigma) unit.sigma = *own.sigma;
  if (own.resonant_frequency_hz) unit.resonant_frequency_hz = *own.resonant_frequency_hz;
  if (own.temperature_c) unit.temperature_c = *own.temperature_c;
  if (own.temperature_drift_c_per_s)
    unit.temperature_drift_c_per_s = *own.temperature_drift_c_per_s;
  if (own.excite_time_s) unit.excite_time_s = *own.excite_time_s;
  if (own.gyro_stall_after_samples)
    unit.faults.gyro_stall_after_samples = own.gyro_stall_after_samples;
  if (own.gyro_stall_from_run) unit.faults.gyro_stall_from_run = *own.gyro_stall_from_run;
  if (own.gyro_bus_off_after_samples)
    unit.faults.gyro_bus_off_after_samples = own.gyro_bus_off_after_samples;
  if (own.gyro_drop_every_nth_sample)
    unit.faults.gyro_drop_every_nth_sample = *own.gyro_drop_every_nth_sample;
  if (own.gyro_never_ready) unit.faults.gyro_never_ready = *own.gyro_never_ready;
  return unit;
}

std::string_view ToString(StationKind kind) noexcept {
  return kind == StationKind::kReal ? "real" : "simulated";
}

std::string_view ToString(TableTransport transport) noexcept {
  return transport == TableTransport::kRtu ? "rtu" : "tcp";
}

std::string_view ToString(OmegaSourceSetting setting) noexcept {
  switch (setting) {
    case OmegaSourceSetting::kAngleWhenReported:
      return "angle when reported";
    case OmegaSourceSetting::kAngle:
      return "angle";
    case OmegaSourceSetting::kRate:
      return "rate";
  }
  return "?";
}

std::expected<StationConfig, ConfigError> ParseStationConfig(std::string_view toml_text,
                                                             const std::filesystem::path& file) {
  HRG_TRY(document, ParseTomlText(toml_text, file));
  return ReadStation(*document, file);
}

std::expected<StationConfig, ConfigError> LoadStationConfig(const std::filesystem::path& file) {
  HRG_TRY(document, LoadTomlFile(file));
  HRG_TRY(station, ReadStation(*document, file));
  // A relative SQLite path is the station file's neighbour, not the working directory's: from
  // the cwd, `hrg-results` run elsewhere read (and created) another, empty database.
  if (const auto url = results::ParseResultsUrl(station->results_url);
      url && url->engine == results::Engine::kSqlite &&
      std::filesystem::path(url->sqlite_path).is_relative()) {
    std::error_code ec;
    const std::filesystem::path folder = std::filesystem::absolute(file, ec).parent_path();
    station->results_url = "sqlite://" + (folder / url->sqlite_path).lexically_normal().string();
    station->results_url_relative = true;
  }
  return station;
}

}  // namespace hrgbench::bench
