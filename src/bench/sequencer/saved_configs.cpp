// The configs a session ran with, saved inside it: <dir>/config/{station,sequence,limits}.toml.
// `resume` needs nothing but the session directory, and a session shows exactly what was run.
#include "bench/sequencer/saved_configs.hpp"

#include <fstream>
#include <sstream>

#include "hrgbench/session/session.hpp"

namespace hrgbench::bench::internal {
namespace {

std::expected<std::string, std::string> ReadAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::unexpected(path.string() + ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

std::expected<std::vector<std::pair<std::string, std::string>>, std::string> ConfigCopies(
    const BenchConfigs& configs) {
  const std::pair<const std::filesystem::path*, const char*> files[] = {
      {&configs.station.file, "station.toml"},
      {&configs.sequence.file, "sequence.toml"},
      {&configs.limits.file, "limits.toml"}};
  std::vector<std::pair<std::string, std::string>> copies;
  for (const auto& [source, name] : files) {
    if (source->empty()) continue;  // no limits file
    auto text = ReadAll(*source);
    if (!text) return std::unexpected(text.error());
    copies.emplace_back(std::string("config/") + name, std::move(*text));
  }
  // A prompt's image sits where the sequence names it, relative to the sequence (the loader allows
  // no way out of its folder), so the copy beside config/sequence.toml loads as the original did.
  for (const SequencePrompt& prompt : configs.sequence.prompts) {
    if (prompt.image.empty()) continue;
    auto bytes = ReadAll(prompt.image_file);
    if (!bytes) return std::unexpected(bytes.error());
    copies.emplace_back("config/" + prompt.image, std::move(*bytes));
  }
  // A relative [results] url was resolved against the station file's folder, which the copy in
  // config/ no longer sits in: the resolved URL goes beside it, for resume's upload.
  if (configs.station.results_url_relative)
    copies.emplace_back(kResultsUrlCopy, configs.station.results_url + "\n");
  return copies;
}

std::expected<void, std::string> SaveConfigs(const BenchConfigs& configs,
                                             const std::filesystem::path& dir) {
  auto copies = ConfigCopies(configs);
  if (!copies) return std::unexpected(copies.error());
  if (auto made = session::CreateDirectoriesDurably(dir / "config"); !made)
    return std::unexpected(made.error().ToString());
  for (const auto& [relative, text] : *copies) {
    if (auto made = session::CreateDirectoriesDurably((dir / relative).parent_path()); !made)
      return std::unexpected(made.error().ToString());
    if (auto written = session::WriteFileAtomic(dir / relative, text); !written)
      return std::unexpected(written.error().ToString());
  }
  return {};
}

}  // namespace hrgbench::bench::internal

namespace hrgbench::bench {

std::expected<void, std::string> SaveConfigs(const BenchConfigs& configs,
                                             const std::filesystem::path& dir) {
  return internal::SaveConfigs(configs, dir);
}

std::expected<BenchConfigs, std::string> LoadSavedConfigs(const std::filesystem::path& dir,
                                                          const nlohmann::json& hashes,
                                                          const std::string& recorded_in) {
  const std::filesystem::path config = dir / "config";
  const std::filesystem::path limits =
      std::filesystem::exists(config / "limits.toml") ? config / "limits.toml" : "";
  auto configs = LoadBenchConfigs(config / "station.toml", config / "sequence.toml", limits);
  if (!configs) return std::unexpected(configs.error().ToString());
  if (configs->station.results_url_relative) {
    // The URL as run (ConfigCopies); a session saved before that file existed keeps the old
    // reading of the written path: from the working directory.
    auto resolved = internal::ReadAll(dir / internal::kResultsUrlCopy);
    if (resolved) {
      while (!resolved->empty() && (resolved->back() == '\n' || resolved->back() == '\r'))
        resolved->pop_back();
      configs->station.results_url = *resolved;
    } else if (auto written =
                   ParseStationConfig(internal::ReadAll(config / "station.toml").value_or(""),
                                      config / "station.toml")) {
      configs->station.results_url = written->results_url;
    }
  }
  // The copies must be the files the session recorded (a hand-edited copy is not the same run).
  const std::pair<const char*, const std::string*> checks[] = {
      {"station", &configs->station.sha256_hex},
      {"sequence", &configs->sequence.sha256_hex},
      {"limits", &configs->limits.sha256_hex}};
  for (const auto& [key, actual] : checks) {
    const nlohmann::json expected =
        hashes.is_object() ? hashes.value(key, nlohmann::json()) : nlohmann::json();
    const std::string want = expected.is_string() ? expected.get<std::string>() : "";
    if (want != *actual)
      return std::unexpected((config / (std::string(key) + ".toml")).string() + ": SHA-256 " +
                             (actual->empty() ? "(none)" : *actual) +
                             " differs from the one recorded in " + recorded_in + " (" +
                             (want.empty() ? "(none)" : want) + ")");
  }
  return std::move(*configs);
}

std::expected<BenchConfigs, std::string> LoadSavedConfigs(const std::filesystem::path& dir) {
  session::ReadOptions options;
  options.load_samples = false;
  auto recorded = session::ReadSession(dir, options);
  if (!recorded) return std::unexpected(recorded.error().ToString());
  return LoadSavedConfigs(dir, recorded->document.value("config_sha256", nlohmann::json::object()),
                          "session.json");
}

}  // namespace hrgbench::bench
