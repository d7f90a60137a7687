#include "sim/gyro_sim_config.hpp"

#include <toml++/toml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <system_error>

namespace hrgbench::drivers::sim {
namespace {

// Bounds on the file (the same as the bench's config files, bench/config_bounds.hpp, which a driver
// does not include): the example is 1 KiB; a host name has at most 253 bytes.
constexpr std::size_t kMaxFileBytes = std::size_t{1} << 20;
constexpr std::size_t kMaxNameBytes = 255;
constexpr std::size_t kMaxShownValue = 80;

// A value as shown in a message: control characters escaped (a NUL would cut the message short in
// a C string, a line feed would split it), cut to kMaxShownValue characters.
std::string Shown(std::string_view text) {
  std::string shown;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7F) {
      char code[8];
      std::snprintf(code, sizeof(code), "\\u%04X", c);
      shown += code;
    } else {
      shown += ch;
    }
    if (shown.size() >= kMaxShownValue) return shown + "...";
  }
  return shown;
}

// Error messages: "<file>:<line>: <key> = <value>: <what>".
class Reader {
 public:
  explicit Reader(std::string_view source) : source_(source) {}

  std::string Where(const toml::node* node, std::string_view key) const {
    std::ostringstream os;
    os << source_;
    if (node != nullptr) os << ":" << node->source().begin.line;
    os << ": " << key;
    if (node != nullptr) {
      os << " = ";
      if (node->is_string()) {
        os << '"' << Shown(node->value_or(std::string())) << '"';
      } else if (node->is_value() || node->is_array()) {
        std::ostringstream value;
        value << toml::toml_formatter(*node);
        os << Shown(value.str());
      }
    }
    return os.str();
  }

  bool CheckKeys(const toml::table& table, std::string_view prefix,
                 std::initializer_list<std::string_view> allowed, std::string* error) const {
    for (const auto& [key, node] : table) {
      bool known = false;
      for (std::string_view a : allowed) known = known || key.str() == a;
      if (!known) {
        *error = Where(&node, std::string(prefix) + std::string(key.str())) + ": unknown key";
        return false;
      }
    }
    return true;
  }

  bool Number(const toml::table& table, std::string_view prefix, std::string_view key, double* out,
              std::string* error) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) return true;
    const std::optional<double> value = node->value<double>();
    if (!value || !(node->is_floating_point() || node->is_integer())) {
      *error = Where(node, std::string(prefix) + std::string(key)) + ": expected a number";
      return false;
    }
    *out = *value;
    return true;
  }

  template <typename Int>
  bool Integer(const toml::table& table, std::string_view prefix, std::string_view key, Int* out,
               std::int64_t min, std::int64_t max, std::string* error) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) return true;
    const std::optional<std::int64_t> value =
        node->is_integer() ? node->value<std::int64_t>() : std::nullopt;
    if (!value || *value < min || *value > max) {
      std::ostringstream os;
      os << ": expected an integer in [" << min << ", " << max << "]";
      *error = Where(node, std::string(prefix) + std::string(key)) + os.str();
      return false;
    }
    *out = static_cast<Int>(*value);
    return true;
  }

  bool Bool(const toml::table& table, std::string_view prefix, std::string_view key, bool* out,
            std::string* error) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) return true;
    if (!node->is_boolean()) {
      *error = Where(node, std::string(prefix) + std::string(key)) + ": expected true or false";
      return false;
    }
    *out = node->value_or(false);
    return true;
  }

  template <typename Vector>
  bool Vec(const toml::table& table, std::string_view prefix, std::string_view key, Vector* out,
           std::string* error) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) return true;
    const toml::array* array = node->as_array();
    const auto n = static_cast<std::size_t>(out->size());
    if (array == nullptr || array->size() != n) {
      std::ostringstream os;
      os << ": expected an array of " << n << " numbers";
      *error = Where(node, std::string(prefix) + std::string(key)) + os.str();
      return false;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::optional<double> v = (*array)[i].value<double>();
      if (!v) {
        *error = Where(node, std::string(prefix) + std::string(key)) + ": element is not a number";
        return false;
      }
      (*out)(static_cast<Eigen::Index>(i)) = *v;
    }
    return true;
  }

 private:
  std::string source_;
};

const toml::table* SubTable(const toml::table& root, std::string_view name) {
  const toml::node* node = root.get(name);
  return node == nullptr ? nullptr : node->as_table();
}

}  // namespace

std::expected<GyroSimFileConfig, std::string> ParseGyroSimConfig(std::string_view toml_text,
                                                                 std::string_view source_name) {
  if (toml_text.size() > kMaxFileBytes) {
    return std::unexpected(std::string(source_name) + ": file too large: more than " +
                           std::to_string(kMaxFileBytes) + " bytes");
  }
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << source_name << ":" << e.source().begin.line << ": " << e.description();
    return std::unexpected(os.str());
  }
  const Reader r(source_name);
  GyroSimFileConfig config;
  GyroSimOptions& o = config.options;
  std::string error;
  if (!r.CheckKeys(root, "", {"model", "electronics", "omega", "faults"}, &error)) {
    return std::unexpected(error);
  }
  for (std::string_view name : {"model", "electronics", "omega", "faults"}) {
    const toml::node* node = root.get(name);
    if (node != nullptr && !node->is_table()) {
      return std::unexpected(r.Where(node, name) + ": expected a table");
    }
  }
  bool ok = true;
  if (const toml::table* t = SubTable(root, "model")) {
    ok = r.CheckKeys(*t, "model.", {"delta", "xi", "sigma", "seed"}, &error) &&
         r.Vec(*t, "model.", "delta", &o.delta, &error) &&
         r.Vec(*t, "model.", "xi", &o.xi, &error) &&
         r.Number(*t, "model.", "sigma", &o.sigma, &error) &&
         r.Integer(*t, "model.", "seed", &o.seed, 0, INT64_MAX, &error);
  }
  if (const toml::table* t = SubTable(root, "electronics"); ok && t != nullptr) {
    ok = r.CheckKeys(*t, "electronics.",
                     {"excite_time_s", "resonant_frequency_hz", "temperature_c", "supports_fd"},
                     &error) &&
         r.Number(*t, "electronics.", "excite_time_s", &o.excite_time_s, &error) &&
         r.Number(*t, "electronics.", "resonant_frequency_hz", &o.resonant_frequency_hz, &error) &&
         r.Number(*t, "electronics.", "temperature_c", &o.temperature_c, &error) &&
         r.Bool(*t, "electronics.", "supports_fd", &o.supports_fd, &error);
  }
  if (const toml::table* t = SubTable(root, "omega"); ok && t != nullptr) {
    OmegaConfig& w = config.omega;
    ok = r.CheckKeys(*t, "omega.",
                     {"source", "omega_rad_s", "modbus_host", "modbus_port", "earth_rate_rad_s",
                      "poll_period_ms"},
                     &error) &&
         r.Number(*t, "omega.", "omega_rad_s", &w.omega_rad_s, &error) &&
         r.Number(*t, "omega.", "earth_rate_rad_s", &w.earth_rate_rad_s, &error) &&
         r.Integer(*t, "omega.", "modbus_port", &w.modbus_port, 1, 65535, &error) &&
         r.Integer(*t, "omega.", "poll_period_ms", &w.poll_period_ms, 1, 10000, &error);
    if (ok) {
      if (const toml::node* n = t->get("source")) {
        const std::string s = n->value_or(std::string());
        if (s == "constant") {
          w.source = OmegaConfig::Source::kConstant;
        } else if (s == "modbus") {
          w.source = OmegaConfig::Source::kModbus;
        } else {
          return std::unexpected(r.Where(n, "omega.source") +
                                 ": expected \"constant\" or \"modbus\"");
        }
      }
      if (const toml::node* n = t->get("modbus_host")) {
        if (!n->is_string())
          return std::unexpected(r.Where(n, "omega.modbus_host") + ": expected a string");
        w.modbus_host = n->value_or(std::string());
        bool printable = true;
        for (const char c : w.modbus_host) {
          printable = printable && static_cast<unsigned char>(c) >= 0x20 && c != 0x7F;
        }
        if (w.modbus_host.empty() || w.modbus_host.size() > kMaxNameBytes || !printable) {
          return std::unexpected(r.Where(n, "omega.modbus_host") +
                                 ": expected a host name: 1 to 255 bytes, no control characters");
        }
      }
    }
  }
  if (const toml::table* t = SubTable(root, "faults"); ok && t != nullptr) {
    GyroSimFaults& f = o.faults;
    ok = r.CheckKeys(*t, "faults.",
                     {"drop_sample_frames", "drop_every_nth_frame", "corrupt_sample_frames",
                      "stall_after_samples", "ignore_commands", "no_reply", "bus_off_after_samples",
                      "fault_bits"},
                     &error) &&
         r.Integer(*t, "faults.", "drop_sample_frames", &f.drop_sample_frames, 0, UINT32_MAX,
                   &error) &&
         r.Integer(*t, "faults.", "drop_every_nth_frame", &f.drop_every_nth_frame, 0, UINT32_MAX,
                   &error) &&
         r.Integer(*t, "faults.", "corrupt_sample_frames", &f.corrupt_sample_frames, 0, UINT32_MAX,
                   &error) &&
         r.Integer(*t, "faults.", "stall_after_samples", &f.stall_after_samples, -1, INT64_MAX,
                   &error) &&
         r.Integer(*t, "faults.", "ignore_commands", &f.ignore_commands, 0, UINT32_MAX, &error) &&
         r.Bool(*t, "faults.", "no_reply", &f.no_reply, &error) &&
         r.Integer(*t, "faults.", "bus_off_after_samples", &f.bus_off_after_samples, -1, INT64_MAX,
                   &error) &&
         r.Integer(*t, "faults.", "fault_bits", &f.fault_bits, 0, 255, &error);
  }
  if (!ok) return std::unexpected(error);
  if (std::string why; !o.IsValid(&why)) {
    return std::unexpected(std::string(source_name) + ": " + why);
  }
  return config;
}

std::expected<GyroSimFileConfig, std::string> LoadGyroSimConfig(const std::string& path) {
  // An ifstream opens a directory and reads it as empty, which would load the defaults silently.
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(status)) {
    return std::unexpected(path + ": is a directory, not a file");
  }
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    return std::unexpected(path + ": not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::unexpected(path + ": cannot open");
  std::string text(kMaxFileBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) return std::unexpected(path + ": read error");
  text.resize(static_cast<std::size_t>(in.gcount()));
  return ParseGyroSimConfig(text, path);
}

}  // namespace hrgbench::drivers::sim
