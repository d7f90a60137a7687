// Loader of station files. Reads table by table; each table reader reports its unknown keys last,
// so a misspelt key is reported even when everything else is right.

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>

#include "bench/config/simulated_carrier_table.hpp"
#include "hrgbench/bench/station_config.hpp"
#include "hrgbench/config_file/config_bounds.hpp"
#include "hrgbench/config_file/toml_reader.hpp"
#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/results/results_url.hpp"

namespace hrgbench::bench {
namespace {

using namespace config_file;  // NOLINT(google-build-using-namespace): the loader's vocabulary

constexpr double kInf = std::numeric_limits<double>::infinity();
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

std::expected<GyroLinkConfig, ConfigError> ReadGyro(TableReader& reader, StationKind kind) {
  GyroLinkConfig gyro;
  HRG_TRY(fd, OptionalBool(reader, "fd", gyro.fd));
  gyro.fd = *fd;
  if (kind == StationKind::kReal) {
    HRG_TRY(iface, RequiredString(reader, "can_interface"));
    // IFNAMSIZ is 16 including the terminating zero.
    if (iface->size() > 15) {
      return std::unexpected(reader.Error(*reader.table().get("can_interface"), "can_interface",
                                          "out of range: a Linux interface name has <= 15 "
                                          "characters"));
    }
    gyro.can_interface = *iface;
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
    for (std::string_view key : {"can_interface", "bitrate", "data_bitrate"})
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
  // The electronics' output low-pass: what colours the pick-off noise (output_filter.hpp).
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
  HRG_CHECK(
      reader.Unknown("can_interface, bitrate, fd, data_bitrate, ack_timeout_ms, command_attempts, "
                     "status_poll_ms, sample_timeout_ms, output_filter, output_filter_order, "
                     "output_filter_cutoff_hz"));
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

std::expected<SimulatedFaults, ConfigError> ReadFaults(TableReader& reader) {
  SimulatedFaults faults;
  constexpr std::int64_t kMaxCount = std::numeric_limits<std::int64_t>::max();
  HRG_TRY(never_stable, OptionalBool(reader, "table_never_stable", false));
  faults.table_never_stable = *never_stable;
  // Absent means never; a time beyond any session is a typo, not a way to say never.
  constexpr Range kFaultTime{0.0, kMaxLongWaitS, true, "in [0, 86400] s (a day)"};
  HRG_TRY(fault_after, MaybeNumber(reader, "table_fault_after_s", kFaultTime));
  faults.table_fault_after_s = *fault_after;
  HRG_TRY(silent_after, MaybeNumber(reader, "table_unresponsive_after_s", kFaultTime));
  faults.table_unresponsive_after_s = *silent_after;
  HRG_TRY(stall, MaybeInteger(reader, "gyro_stall_after_samples", 0, kMaxCount));
  faults.gyro_stall_after_samples = *stall;
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
  HRG_CHECK(reader.Unknown(
      "table_never_stable, table_fault_after_s, table_unresponsive_after_s, "
      "gyro_stall_after_samples, gyro_bus_off_after_samples, gyro_drop_every_nth_sample, "
      "gyro_never_ready"));
  return faults;
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
      HRG_TRY(carrier_config, internal::ReadSimulatedCarrier(carrier_reader));
      sim.carrier = *carrier_config;
    }
  } else {
    HRG_CHECK(
        Forbid(reader, "carrier", "[simulated.carrier] applies only to physics = \"carrier\""));
  }
  if (!carrier && reader.table().get("delta") != nullptr) {
    HRG_TRY(delta, RequiredVector<6>(reader, "delta", kAnyFinite));
    sim.delta = *delta;
  } else if (!carrier) {
    reader.Find("delta");
  }
  if (!carrier && reader.table().get("xi") != nullptr) {
    // Each |ξi| < 1/4 keeps I + C(ξ) invertible (estimator/model.hpp).
    HRG_TRY(xi, RequiredVector<4>(reader, "xi",
                                  {-0.25, 0.25, false,
                                   "in (-0.25, 0.25) so that I + C(xi) is "
                                   "invertible",
                                   false}));
    sim.xi = *xi;
  } else if (!carrier) {
    reader.Find("xi");
  }
  if (!carrier) {
    HRG_TRY(sigma, OptionalNumber(reader, "sigma", {0.0, 1.0, true, "in [0, 1]"}, sim.sigma));
    sim.sigma = *sigma;
  }
  HRG_TRY(seed, OptionalInteger(reader, "seed", 0, std::numeric_limits<std::int64_t>::max(), 1));
  sim.seed = static_cast<std::uint64_t>(*seed);
  // The electronics report it in a 24-bit mHz field: the simulated ones refuse more.
  if (!carrier) {
    HRG_TRY(f,
            OptionalNumber(reader, "resonant_frequency_hz",
                           {0.0, hw::kMaxReportedResonantFrequencyHz, false, "in (0, 16777.215]"},
                           sim.resonant_frequency_hz));
    sim.resonant_frequency_hz = *f;
  }
  HRG_TRY(t, OptionalNumber(reader, "temperature_c", {-60.0, 150.0, true, "in [-60, 150]"},
                            sim.temperature_c));
  sim.temperature_c = *t;
  HRG_TRY(drift, OptionalNumber(reader, "temperature_drift_c_per_s",
                                {-1.0, 1.0, true, "in [-1, 1]"}, sim.temperature_drift_c_per_s));
  sim.temperature_drift_c_per_s = *drift;
  HRG_TRY(excite, OptionalNumber(reader, "excite_time_s", {0.0, 600.0, true, "in [0, 600]"},
                                 sim.excite_time_s));
  sim.excite_time_s = *excite;
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
    HRG_TRY(faults, ReadFaults(faults_reader));
    sim.faults = *faults;
  }
  HRG_CHECK(reader.Unknown(
      "faster_than_real_time, time_scale, physics, delta, xi, sigma, seed, resonant_frequency_hz, "
      "temperature_c, temperature_drift_c_per_s, excite_time_s, table_settle_time_constant_s, "
      "table_noise_rad_s, table_encoder_counts_per_rev, table_encoder_noise_rad, "
      "table_stable_tolerance_rad_s, table_stable_hold_s, [simulated.carrier], "
      "[simulated.faults]"));
  return sim;
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
    HRG_TRY(gyro, ReadGyro(reader, station.kind));
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

  HRG_CHECK(root.Unknown("[station], [site], [gyro], [table], [simulated], [realtime], [results]"));
  return station;
}

}  // namespace

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
  return ReadStation(*document, file);
}

}  // namespace hrgbench::bench
