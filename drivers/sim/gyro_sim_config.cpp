// Loader of the hrg-gyro-sim config file, on the project's one strict config-file reader
// (hrgbench/config/toml_reader.hpp): the same messages, bounds and file checks as the bench's
// configs. Each table reader reports its unknown keys last, so a misspelt key is reported even
// when everything else is right.

#include "sim/gyro_sim_config.hpp"

#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "hrgbench/config/toml_reader.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "sim/carrier_config.hpp"

namespace hrgbench::drivers::sim {
namespace {

using namespace config_file;  // NOLINT(google-build-using-namespace): the loader's vocabulary

constexpr std::int64_t kInt64Max = std::numeric_limits<std::int64_t>::max();
constexpr std::int64_t kUint32Max = std::numeric_limits<std::uint32_t>::max();

// GyroSimOptions::IsValid's ranges (gyro_sim_options.hpp), checked here as well so that an error
// names the line and the value as written.
constexpr Range kXi{-kMaxAbsXi, kMaxAbsXi, false,
                    "in (-0.25, 0.25) (the distortion is a small perturbation)", false};
constexpr Range kExciteTime{0.0, kMaxExciteTimeS, true, "in [0, 600]"};
constexpr Range kResonantFrequency{0.0, hw::kMaxReportedResonantFrequencyHz, false,
                                   "in (0, 16777.215] (the status field's range)"};
constexpr Range kTemperature{-kMaxAbsTemperatureC, kMaxAbsTemperatureC, true,
                             "in [-327.67, 327.67]"};

// Optional keys: absent leaves *out (its in-class default) as it is.
std::expected<void, ConfigError> ReadNumber(TableReader& reader, std::string_view key,
                                            const Range& range, double* out) {
  HRG_TRY(v, OptionalNumber(reader, key, range, *out));
  *out = *v;
  return {};
}

template <typename Int>
std::expected<void, ConfigError> ReadInteger(TableReader& reader, std::string_view key,
                                             std::int64_t min, std::int64_t max, Int* out) {
  HRG_TRY(v, OptionalInteger(reader, key, min, max, static_cast<std::int64_t>(*out)));
  *out = static_cast<Int>(*v);
  return {};
}

std::expected<void, ConfigError> ReadBool(TableReader& reader, std::string_view key, bool* out) {
  HRG_TRY(v, OptionalBool(reader, key, *out));
  *out = *v;
  return {};
}

template <int N>
std::expected<void, ConfigError> ReadVector(TableReader& reader, std::string_view key,
                                            const Range& range, Eigen::Matrix<double, N, 1>* out) {
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return {};
  HRG_TRY(v, VectorFrom<N>(reader, *node, key, range));
  *out = *v;
  return {};
}

std::expected<void, ConfigError> ReadModel(TableReader& reader, GyroSimOptions* o) {
  HRG_TRY(physics,
          Choice(reader, "physics", {"slow", "carrier"}, o->physics == GyroPhysics::kSlow ? 0 : 1));
  o->physics = *physics == 0 ? GyroPhysics::kSlow : GyroPhysics::kCarrier;
  if (o->physics == GyroPhysics::kSlow) {
    HRG_TRY(delta, ReadVector<6>(reader, "delta", kAnyFinite, &o->delta));
    HRG_TRY(xi, ReadVector<4>(reader, "xi", kXi, &o->xi));
    HRG_TRY(sigma, ReadNumber(reader, "sigma", kNonNegative, &o->sigma));
  } else {
    // The carrier physics has its own truth and noise ([carrier]); these would be ignored.
    for (std::string_view key : {"delta", "xi", "sigma"}) {
      HRG_CHECK(Forbid(reader, key,
                       "applies only to physics = \"slow\" (physics = \"carrier\" takes its "
                       "parameters from [carrier])"));
    }
  }
  HRG_TRY(seed, ReadInteger(reader, "seed", 0, kInt64Max, &o->seed));
  HRG_CHECK(reader.Unknown("physics, delta, xi, sigma, seed"));
  return {};
}

std::expected<void, ConfigError> ReadElectronics(TableReader& reader, GyroSimOptions* o) {
  HRG_TRY(excite, ReadNumber(reader, "excite_time_s", kExciteTime, &o->excite_time_s));
  HRG_TRY(frequency, ReadNumber(reader, "resonant_frequency_hz", kResonantFrequency,
                                &o->resonant_frequency_hz));
  HRG_TRY(temperature, ReadNumber(reader, "temperature_c", kTemperature, &o->temperature_c));
  HRG_TRY(fd, ReadBool(reader, "supports_fd", &o->supports_fd));
  HRG_TRY(node, ReadInteger(reader, "node", 0, gyro_can::kMaxNodeId, &o->node));
  HRG_CHECK(
      reader.Unknown("excite_time_s, resonant_frequency_hz, temperature_c, supports_fd, node"));
  return {};
}

std::expected<void, ConfigError> ReadOmega(TableReader& reader, OmegaConfig* w) {
  HRG_TRY(source, Choice(reader, "source", {"constant", "modbus"},
                         w->source == OmegaConfig::Source::kConstant ? 0 : 1));
  w->source = *source == 0 ? OmegaConfig::Source::kConstant : OmegaConfig::Source::kModbus;
  HRG_TRY(omega, ReadNumber(reader, "omega_rad_s", kAnyFinite, &w->omega_rad_s));
  // A host name: 1 to kMaxNameBytes (255) bytes, no control characters.
  HRG_TRY(host, OptionalString(reader, "modbus_host", w->modbus_host, true));
  w->modbus_host = std::move(*host);
  HRG_TRY(port, ReadInteger(reader, "modbus_port", 1, 65535, &w->modbus_port));
  HRG_TRY(earth, ReadNumber(reader, "earth_rate_rad_s", kAnyFinite, &w->earth_rate_rad_s));
  HRG_TRY(poll, ReadInteger(reader, "poll_period_ms", 1, 10000, &w->poll_period_ms));
  HRG_CHECK(reader.Unknown(
      "source, omega_rad_s, modbus_host, modbus_port, earth_rate_rad_s, poll_period_ms"));
  return {};
}

std::expected<void, ConfigError> ReadFaults(TableReader& reader, GyroSimFaults* f) {
  HRG_TRY(drop, ReadInteger(reader, "drop_sample_frames", 0, kUint32Max, &f->drop_sample_frames));
  HRG_TRY(nth,
          ReadInteger(reader, "drop_every_nth_frame", 0, kUint32Max, &f->drop_every_nth_frame));
  HRG_TRY(corrupt,
          ReadInteger(reader, "corrupt_sample_frames", 0, kUint32Max, &f->corrupt_sample_frames));
  HRG_TRY(stall,
          ReadInteger(reader, "stall_after_samples", -1, kInt64Max, &f->stall_after_samples));
  HRG_TRY(ignore, ReadInteger(reader, "ignore_commands", 0, kUint32Max, &f->ignore_commands));
  HRG_TRY(no_reply, ReadBool(reader, "no_reply", &f->no_reply));
  HRG_TRY(bus_off,
          ReadInteger(reader, "bus_off_after_samples", -1, kInt64Max, &f->bus_off_after_samples));
  HRG_TRY(bits, ReadInteger(reader, "fault_bits", 0, 255, &f->fault_bits));
  HRG_TRY(power_loss,
          ReadInteger(reader, "power_loss_on_commit", 0, kUint32Max, &f->power_loss_on_commit));
  HRG_TRY(corrupt_word,
          ReadInteger(reader, "corrupt_parameter_word", -1, gyro_can::kParameterBlockWords - 1,
                      &f->corrupt_parameter_word));
  HRG_CHECK(reader.Unknown(
      "drop_sample_frames, drop_every_nth_frame, corrupt_sample_frames, stall_after_samples, "
      "ignore_commands, no_reply, bus_off_after_samples, fault_bits, power_loss_on_commit, "
      "corrupt_parameter_word"));
  return {};
}

std::expected<GyroSimFileConfig, ConfigError> ReadConfig(const TomlDocument& document,
                                                         const std::filesystem::path& file) {
  const Source source(file, document.text);
  TableReader root(document.root, "", source);
  GyroSimFileConfig config;
  HRG_TRY(model, SubTable(root, "model", false));
  if (*model != nullptr) {
    TableReader reader(**model, "model", source);
    HRG_TRY(model_read, ReadModel(reader, &config.options));
  }
  HRG_TRY(electronics, SubTable(root, "electronics", false));
  if (*electronics != nullptr) {
    TableReader reader(**electronics, "electronics", source);
    HRG_TRY(electronics_read, ReadElectronics(reader, &config.options));
  }
  HRG_TRY(omega, SubTable(root, "omega", false));
  if (*omega != nullptr) {
    TableReader reader(**omega, "omega", source);
    HRG_TRY(omega_read, ReadOmega(reader, &config.omega));
  }
  const bool carrier = config.options.physics == GyroPhysics::kCarrier;
  if (carrier) {
    HRG_TRY(carrier_table, SubTable(root, "carrier", false));
    if (*carrier_table != nullptr) {
      TableReader reader(**carrier_table, "carrier", source);
      HRG_TRY(carrier_read, ReadCarrierTable(reader, &config.options.carrier));
    }
  } else {
    HRG_CHECK(Forbid(root, "carrier", "[carrier] applies only to [model] physics = \"carrier\""));
  }
  HRG_TRY(faults, SubTable(root, "faults", false));
  if (*faults != nullptr) {
    TableReader reader(**faults, "faults", source);
    HRG_TRY(faults_read, ReadFaults(reader, &config.options.faults));
  }
  HRG_CHECK(root.Unknown("[model], [electronics], [omega], [carrier], [faults]"));
  // Every range IsValid checks was checked above at its key; this is the options' own contract.
  if (std::string why; !config.options.IsValid(&why))
    return std::unexpected(ConfigError{file, 0, "", "", std::move(why)});
  return config;
}

}  // namespace

std::expected<GyroSimFileConfig, ConfigError> ParseGyroSimConfig(
    std::string_view toml_text, const std::filesystem::path& file) {
  HRG_TRY(document, ParseTomlText(toml_text, file));
  return ReadConfig(*document, file);
}

std::expected<GyroSimFileConfig, ConfigError> LoadGyroSimConfig(const std::filesystem::path& file) {
  HRG_TRY(document, LoadTomlFile(file));
  return ReadConfig(*document, file);
}

}  // namespace hrgbench::drivers::sim
