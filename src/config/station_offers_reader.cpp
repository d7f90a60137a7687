#include "station_offers_reader.hpp"

#include <algorithm>
#include <string>

namespace hrgbench::bench::internal {
namespace {

using config_file::ConfigError;
using config_file::TableReader;

constexpr std::size_t kMaxOffered = 64;  // a station offers a handful; more is a mistake

// A list of .toml file names (no folder part), each once; absent: empty. Whether each exists is
// the panel's check (panel_catalog.hpp): a copy of a station file elsewhere still runs sessions.
std::expected<std::vector<std::string>, ConfigError> Files(TableReader& reader,
                                                           std::string_view key) {
  std::vector<std::string> names;
  const toml::node* node = reader.Find(key);
  if (node == nullptr) return names;
  const toml::array* array = node->as_array();
  if (array == nullptr || array->empty() || array->size() > kMaxOffered)
    return std::unexpected(reader.Error(*node, key,
                                        "expected an array of 1 to " + std::to_string(kMaxOffered) +
                                            " file names beside the station file"));
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = *array->get(i);
    const std::string element_key = std::string(key) + "[" + std::to_string(i) + "]";
    const auto* text = element.as_string();
    if (text == nullptr) return std::unexpected(reader.Error(element, element_key, "not a string"));
    const std::string name = text->get();
    if (name.empty() || name.find('/') != std::string::npos || name.front() == '.' ||
        !name.ends_with(".toml"))
      return std::unexpected(
          reader.Error(element, element_key,
                       "a .toml file name in the station file's folder, without a folder"));
    if (std::find(names.begin(), names.end(), name) != names.end())
      return std::unexpected(reader.Error(element, element_key, "offered twice"));
    names.push_back(name);
  }
  return names;
}

// A default: one of `offered` (when given), else a file name.
std::expected<std::string, ConfigError> Default(TableReader& reader, std::string_view key,
                                                const std::vector<std::string>& offered,
                                                std::string_view list_key) {
  HRG_TRY(name, config_file::OptionalString(reader, key, "", false));
  if (name->empty()) return *name;
  const toml::node& node = *reader.table().get(key);
  if (!offered.empty()) {
    if (std::find(offered.begin(), offered.end(), *name) == offered.end())
      return std::unexpected(
          reader.Error(node, key, "not one of " + std::string(list_key) + " (the files offered)"));
    return *name;
  }
  if (name->find('/') != std::string::npos || !name->ends_with(".toml"))
    return std::unexpected(reader.Error(
        node, key, "a .toml file name in the station file's folder, without a folder"));
  return *name;
}

}  // namespace

std::expected<StationOffers, ConfigError> ReadOffers(TableReader& reader, StationKind kind) {
  StationOffers offers;
  offers.declared = true;
  HRG_TRY(sequences, Files(reader, "sequences"));
  offers.sequences = std::move(*sequences);
  HRG_TRY(limits, Files(reader, "limits"));
  offers.limits = std::move(*limits);
  HRG_TRY(default_sequence, Default(reader, "default_sequence", offers.sequences, "sequences"));
  offers.default_sequence = std::move(*default_sequence);
  HRG_TRY(default_limits, Default(reader, "default_limits", offers.limits, "limits"));
  offers.default_limits = std::move(*default_limits);
  HRG_TRY(no_limits, config_file::OptionalBool(reader, "no_limits", false));
  if (*no_limits && kind == StationKind::kReal)
    return std::unexpected(
        reader.Error(*reader.table().get("no_limits"), "no_limits",
                     "a production station (kind = \"real\") never offers a session without "
                     "limits: its sessions are judged"));
  offers.no_limits = *no_limits;
  HRG_CHECK(reader.Unknown("sequences, default_sequence, limits, default_limits, no_limits"));
  return offers;
}

}  // namespace hrgbench::bench::internal
