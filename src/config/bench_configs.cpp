#include "hrgbench/config/bench_configs.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "count_text.hpp"
#include "hrgbench/estimator/identifiability.hpp"
#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/hw/gyro_link_load.hpp"
#include "hrgbench/session/number_text.hpp"

namespace hrgbench::bench {
namespace {

using config_file::ConfigError;

// The loaded value, as close to the written one as a double allows.
std::string Shortest(double v) { return session::NumberText(v); }

hw::GyroLinkPlan LinkPlan(const StationConfig& station, std::uint32_t sample_rate_hz) {
  hw::GyroLinkPlan plan;
  plan.sample_rate_hz = sample_rate_hz;
  plan.can_fd = station.gyro.fd;
  plan.nominal_bit_rate_bps = station.gyro.bitrate;
  plan.data_bit_rate_bps = station.gyro.data_bitrate;
  return plan;
}

// A bus and the fitted positions on it.
struct SharedBus {
  std::string interface;
  std::vector<std::string> positions;
};

// The station's buses, in the order of their first fitted position.
std::vector<SharedBus> BusesOf(const StationConfig& station) {
  std::vector<SharedBus> buses;
  for (const FixturePosition* position : FittedPositions(station)) {
    auto it = std::find_if(buses.begin(), buses.end(), [position](const SharedBus& bus) {
      return bus.interface == position->can_interface;
    });
    if (it == buses.end()) it = buses.insert(buses.end(), {position->can_interface, {}});
    it->positions.push_back(position->name);
  }
  return buses;
}

// The bus that carries the most units (the first among equals): every unit runs the same sequence
// at the same time, so that bus is the one the plan must fit.
SharedBus BusiestBus(const StationConfig& station) {
  SharedBus busiest;
  for (SharedBus& bus : BusesOf(station))
    if (bus.positions.size() > busiest.positions.size()) busiest = std::move(bus);
  return busiest;
}

// `units` units' links on one bus.
hw::GyroLinkLoad BusLoad(const StationConfig& station, std::uint32_t sample_rate_hz,
                         std::size_t units) {
  hw::GyroLinkLoad load = hw::WorstCaseLinkLoad(LinkPlan(station, sample_rate_hz));
  load.frames_per_s *= static_cast<double>(units);
  load.bus_share *= static_cast<double>(units);
  return load;
}

// The busiest run's load on a bus carrying `bus->units` units, into `bus`.
void JudgeBusiestRun(const BenchConfigs& configs, PlannedBusLoad* bus) {
  for (const SequenceRun& run : configs.sequence.runs) {
    const hw::GyroLinkLoad load = BusLoad(configs.station, run.sample_rate_hz, bus->units);
    if (load.bus_share > bus->load.bus_share) {
      bus->load = load;
      bus->sample_rate_hz = run.sample_rate_hz;
    }
  }
}

std::string BusName(const StationConfig& station) {
  const std::string rates =
      std::to_string(station.gyro.bitrate / 1000) + " kbit/s" +
      (station.gyro.fd ? ", FD data " + std::to_string(station.gyro.data_bitrate / 1000) + " kbit/s"
                       : "");
  const std::vector<const FixturePosition*> fitted = FittedPositions(station);
  const SharedBus busiest = BusiestBus(station);
  if (busiest.positions.size() > 1) {
    std::string names;
    for (const std::string& name : busiest.positions) names += (names.empty() ? "" : ", ") + name;
    return busiest.interface + " (" + std::to_string(busiest.positions.size()) +
           " units: " + names + ") at " + rates;
  }
  if (fitted.size() > 1) {
    // One unit per bus: each bus carries the same load.
    std::string names;
    for (const FixturePosition* position : fitted)
      names += (names.empty() ? "" : ", ") + position->can_interface;
    return "each unit's own bus (" + names + ") at " + rates;
  }
  return (station.gyro.can_interface.empty() ? "the simulated bus" : station.gyro.can_interface) +
         " at " + rates;
}

// The highest sample rate whose load on the busiest bus is within the planned maximum (the load
// grows with it).
std::uint32_t MaxPlannableRate(const StationConfig& station, std::size_t units) {
  std::uint32_t lo = 0;
  std::uint32_t hi = hw::MaxSampleRateHz(station.gyro.fd);
  while (lo < hi) {
    const std::uint32_t mid = lo + (hi - lo + 1) / 2;
    if (BusLoad(station, mid, units).bus_share <= hw::kMaxPlannedBusShare)
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

std::expected<void, ConfigError> CheckRuns(const BenchConfigs& configs) {
  const StationConfig& station = configs.station;
  const SequenceConfig& sequence = configs.sequence;
  const std::size_t units = BusiestBus(station).positions.size();  // on the busiest bus
  for (std::size_t i = 0; i < sequence.runs.size(); ++i) {
    const SequenceRun& run = sequence.runs[i];
    const std::string run_key = "runs[" + std::to_string(i) + "]";
    if (std::abs(run.omega_rad_s) > station.table.max_rate_rad_s) {
      return std::unexpected(ConfigError{
          sequence.file, run.omega_line, run_key + ".omega_rad_s", Shortest(run.omega_rad_s),
          "out of range for station '" + station.name + "' (" + station.file.string() +
              "): |omega| must be <= table.max_rate_rad_s = " +
              Shortest(station.table.max_rate_rad_s)});
    }
    const std::uint32_t max_rate_hz = hw::MaxSampleRateHz(station.gyro.fd);
    if (run.sample_rate_hz > max_rate_hz) {
      return std::unexpected(ConfigError{
          sequence.file, run.sample_rate_line, run_key + ".sample_rate_hz",
          std::to_string(run.sample_rate_hz),
          "out of range for station '" + station.name + "' (" + station.file.string() + "): " +
              (station.gyro.fd
                   ? "CAN FD carries at most " + std::to_string(max_rate_hz) + " samples/s"
                   : "classic CAN carries at most " + std::to_string(max_rate_hz) +
                         " samples/s; more needs gyro.fd = true")});
    }
    // Every bus must carry its units' plan with room to spare (hw/gyro_link_load.hpp): the
    // busiest one is judged.
    const hw::GyroLinkLoad load = BusLoad(station, run.sample_rate_hz, units);
    if (load.bus_share > hw::kMaxPlannedBusShare) {
      const std::uint32_t fits = MaxPlannableRate(station, units);
      std::string more = station.gyro.fd ? "a faster data phase (gyro.data_bitrate)"
                                         : "CAN FD (gyro.fd = true) or a faster bus";
      if (units > 1) more += ", or fewer units on that bus (another can_interface for some)";
      return std::unexpected(
          ConfigError{sequence.file, run.sample_rate_line, run_key + ".sample_rate_hz",
                      std::to_string(run.sample_rate_hz),
                      std::string(units > 1 ? "the bus " : "the gyro's bus (") + BusName(station) +
                          (units > 1 ? "" : ")") + " would be " + Percent(load.bus_share) +
                          " busy (" + config_file::CountText(load.frames_per_s) +
                          " frames/s, worst-case stuffing), above the planned maximum of " +
                          Percent(hw::kMaxPlannedBusShare) + ": at most " + std::to_string(fits) +
                          " samples/s" + (units > 1 ? " per unit" : "") + " fit; " + more +
                          " would carry more"});
    }
    // The fit assumes one noise shape per session (output_filter.hpp): one rate, and a filter
    // whose memory at that rate is within the estimator's bound.
    const OutputFilter& filter = station.gyro.output_filter;
    if (filter.kind == OutputFilterKind::kNone) continue;
    if (run.sample_rate_hz != sequence.runs.front().sample_rate_hz) {
      return std::unexpected(ConfigError{
          sequence.file, run.sample_rate_line, run_key + ".sample_rate_hz",
          std::to_string(run.sample_rate_hz),
          "station '" + station.name +
              "' declares gyro.output_filter, whose noise shape the fit "
              "assumes for the whole session: every run needs the same sample rate (runs[0] has " +
              std::to_string(sequence.runs.front().sample_rate_hz) + ")"});
    }
    // Every run has runs[0]'s rate (above): the shape is the same for all, computed once.
    if (i == 0 &&
        !estimator::ButterworthNoiseShape(static_cast<int>(filter.order), filter.cutoff_hz,
                                          static_cast<double>(run.sample_rate_hz))) {
      return std::unexpected(
          ConfigError{station.file, 0, "gyro.output_filter_cutoff_hz", Shortest(filter.cutoff_hz),
                      "the filter's noise memory at " + std::to_string(run.sample_rate_hz) +
                          " samples/s (" + sequence.file.string() + ", " + run_key + ") exceeds " +
                          std::to_string(estimator::kMaxNoiseShapeLags) +
                          " samples: the cutoff is too low for that rate"});
    }
  }
  return {};
}

std::expected<void, ConfigError> CheckIdentifiable(const BenchConfigs& configs) {
  // The estimator sees table rate + Earth rate, so the plan is judged on those.
  const double earth_rad_s = EarthRateOnAxisRadS(configs.station.site);
  std::vector<double> omegas;
  for (const SequenceRun& run : configs.sequence.runs)
    omegas.push_back(run.omega_rad_s + earth_rad_s);
  const estimator::IdentifiabilityReport report =
      estimator::CheckRatePlan(omegas, estimator::kAllXi);
  for (const ParameterLimit& limit : configs.limits.limits) {
    const auto q = static_cast<std::size_t>(limit.quantity);
    bool identifiable = true;
    if (q <= static_cast<std::size_t>(LimitedQuantity::kDelta6)) {
      identifiable = report.delta_identifiable[q];
    } else if (q <= static_cast<std::size_t>(LimitedQuantity::kXi4)) {
      identifiable = report.xi_identifiable[q - static_cast<std::size_t>(LimitedQuantity::kXi1)];
    } else if (const auto engineering = EngineeringOf(limit.quantity)) {
      // An engineering quantity needs every parameter it is computed from.
      for (int i = 0; i < 10; ++i) {
        if (!estimator::DependsOn(*engineering, i)) continue;
        identifiable =
            identifiable && (i < 6 ? report.delta_identifiable[static_cast<std::size_t>(i)]
                                   : report.xi_identifiable[static_cast<std::size_t>(i - 6)]);
      }
    }
    if (!identifiable) {
      std::string why;
      for (const std::string& reason : report.reasons) why += (why.empty() ? "" : "; ") + reason;
      return std::unexpected(ConfigError{
          configs.limits.file, limit.line, "limits." + std::string(ToString(limit.quantity)),
          "[" + Shortest(limit.min) + ", " + Shortest(limit.max) + "]",
          "cannot be judged: the sequence " + configs.sequence.file.string() +
              " does not determine it (" + why + ")"});
    }
  }
  return {};
}

// An interim decision of [adaptive] may not be less sure than the final one.
std::expected<void, ConfigError> CheckAdaptive(const BenchConfigs& configs) {
  const std::optional<double>& interim = configs.sequence.adaptive.interim_coverage_factor;
  const double k = configs.limits.decision.coverage_factor;
  if (!interim || *interim >= k) return {};
  return std::unexpected(ConfigError{
      configs.sequence.file, 0, "adaptive.interim_coverage_factor", Shortest(*interim),
      "is below the coverage factor k = " + Shortest(k) + " of " + configs.limits.file.string() +
          ": an interim decision may not be less sure than the final one"});
}

}  // namespace

std::string Percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %%", 100.0 * share);
  return text;
}

PlannedBusLoad BusiestRunLoad(const BenchConfigs& configs) {
  PlannedBusLoad busiest;
  busiest.bus = BusName(configs.station);
  busiest.units = BusiestBus(configs.station).positions.size();
  JudgeBusiestRun(configs, &busiest);
  return busiest;
}

std::vector<PlannedBusLoad> EachBusLoad(const BenchConfigs& configs) {
  std::vector<PlannedBusLoad> loads;
  for (SharedBus& bus : BusesOf(configs.station)) {
    PlannedBusLoad each;
    each.bus = bus.interface;
    each.units = bus.positions.size();
    each.positions = std::move(bus.positions);
    JudgeBusiestRun(configs, &each);
    loads.push_back(std::move(each));
  }
  return loads;
}

std::expected<void, ConfigError> CheckBenchConfigs(const BenchConfigs& configs) {
  if (auto ok = CheckRuns(configs); !ok) return ok;
  if (auto ok = CheckAdaptive(configs); !ok) return ok;
  return CheckIdentifiable(configs);
}

std::expected<BenchConfigs, ConfigError> LoadBenchConfigs(
    const std::filesystem::path& station_path, const std::filesystem::path& sequence_path,
    const std::filesystem::path& limits_path) {
  BenchConfigs configs;
  auto station = LoadStationConfig(station_path);
  if (!station) return std::unexpected(station.error());
  configs.station = std::move(*station);
  auto sequence = LoadSequenceConfig(sequence_path);
  if (!sequence) return std::unexpected(sequence.error());
  configs.sequence = std::move(*sequence);
  if (!limits_path.empty()) {
    auto limits = LoadLimitsConfig(limits_path);
    if (!limits) return std::unexpected(limits.error());
    configs.limits = std::move(*limits);
  }
  if (auto ok = CheckBenchConfigs(configs); !ok) return std::unexpected(ok.error());
  return configs;
}

}  // namespace hrgbench::bench
