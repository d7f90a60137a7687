#include "app/panel/panel_catalog.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>

#include "app/report_job.hpp"
#include "hrgbench/results/results_store.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

// A report there, or one a report job is writing (its link answers "being written" until then).
bool HasReport(const fs::path& session_dir) {
  std::error_code ec;
  if (fs::exists(session_dir / "report" / "report.html", ec)) return true;
  const auto job = ReadReportJob(session_dir);
  return job && *job && (*job)->state == ReportJobState::kRunning;
}

std::vector<fs::path> Matching(const fs::path& dir, std::string_view prefix) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file(ec) && name.rfind(prefix, 0) == 0 &&
        entry.path().extension() == ".toml")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

std::expected<PanelCatalog, std::string> LoadPanelCatalog(const fs::path& station) {
  PanelCatalog catalog;
  catalog.station_file = station;
  auto loaded = bench::LoadStationConfig(station);
  if (!loaded) return std::unexpected(loaded.error().ToString());
  catalog.station = *loaded;
  const bench::StationOffers& offers = catalog.station.offers;
  const fs::path dir = station.parent_path().empty() ? fs::path(".") : station.parent_path();
  // Every name [offers] gives must be a file beside the station (the loader checked the rest).
  const auto missing = [&](const char* key, const std::string& name) -> std::optional<std::string> {
    std::error_code ec;
    if (name.empty() || fs::is_regular_file(dir / name, ec)) return std::nullopt;
    return station.string() + ": [offers] " + key + " = \"" + name +
           "\": no such file beside the station file (in " + dir.string() + ")";
  };
  for (const std::string& name : offers.sequences)
    if (auto problem = missing("sequences", name)) return std::unexpected(*problem);
  for (const std::string& name : offers.limits)
    if (auto problem = missing("limits", name)) return std::unexpected(*problem);
  if (auto problem = missing("default_sequence", offers.default_sequence))
    return std::unexpected(*problem);
  if (auto problem = missing("default_limits", offers.default_limits))
    return std::unexpected(*problem);
  // Declared offers must load (a station that names a file it cannot run is refused); the files
  // merely found beside it are offered when they load.
  const auto files = [&](const std::vector<std::string>& declared, std::string_view prefix) {
    std::vector<fs::path> out;
    for (const std::string& name : declared) out.push_back(dir / name);
    return declared.empty() ? Matching(dir, prefix) : out;
  };
  for (const fs::path& file : files(offers.sequences, "sequence-")) {
    auto configs = bench::LoadBenchConfigs(station, file, {});
    if (!configs) {
      if (!offers.sequences.empty())
        return std::unexpected(station.string() +
                               ": [offers] sequences: " + configs.error().ToString());
      spdlog::warn("panel: {} not offered: {}", file.string(), configs.error().ToString());
      continue;
    }
    const bench::SequenceConfig& seq = configs->sequence;
    char text[160];
    std::snprintf(text, sizeof text, "%zu runs, %.0f s of free run", seq.runs.size(),
                  seq.TotalFreeRunS());
    if (file.filename() == offers.default_sequence)
      catalog.default_sequence = catalog.sequences.size();
    nlohmann::json runs = nlohmann::json::array();
    for (const bench::SequenceRun& run : seq.runs)
      runs.push_back({{"omega_rad_s", run.omega_rad_s},
                      {"a", run.a},
                      {"b", run.b},
                      {"theta_rad", run.theta_rad},
                      {"free_run_s", run.free_run_s},
                      {"sample_rate_hz", run.sample_rate_hz}});
    // The operator's own steps, where they come (the page places them in the plan).
    nlohmann::json prompts = nlohmann::json::array();
    for (const bench::SequencePrompt& prompt : seq.prompts)
      prompts.push_back({{"id", prompt.id},
                         {"at", prompt.at == bench::PromptPoint::kStart       ? "start"
                                : prompt.at == bench::PromptPoint::kBeforeRun ? "before_run"
                                                                              : "end"},
                         {"run", prompt.before_run},
                         {"text", prompt.text}});
    const nlohmann::json plan = {{"warmup",
                                  {{"min_s", seq.warmup.min_s},
                                   {"window_s", seq.warmup.window_s},
                                   {"max_drift_c", seq.warmup.max_drift_c},
                                   {"timeout_s", seq.warmup.timeout_s}}},
                                 {"runs", std::move(runs)},
                                 {"prompts", std::move(prompts)}};
    catalog.sequences.push_back({file, seq.name, text, plan});
  }
  if (catalog.sequences.empty())
    return std::unexpected("no sequence-*.toml beside " + station.string() +
                           " loads with it: the panel has nothing to offer");
  for (const fs::path& file : files(offers.limits, "limits-")) {
    auto configs = bench::LoadBenchConfigs(station, catalog.sequences.front().file, file);
    if (!configs) {
      if (!offers.limits.empty())
        return std::unexpected(station.string() +
                               ": [offers] limits: " + configs.error().ToString());
      spdlog::warn("panel: {} not offered: {}", file.string(), configs.error().ToString());
      continue;
    }
    if (file.filename() == offers.default_limits) catalog.default_limits = catalog.limits.size();
    nlohmann::json limits = nlohmann::json::array();
    for (const bench::ParameterLimit& limit : configs->limits.limits)
      limits.push_back({{"quantity", std::string(bench::ToString(limit.quantity))},
                        {"min", limit.min},
                        {"max", limit.max}});
    // The checks of each run's fit against the file's [fit] (analysis/verdict.hpp, FitCheck):
    // the Ω offset only where Ω is fitted, so the page marks a check no result came for.
    const nlohmann::json fit = {"residual_ratio", "whiteness_z", "omega_offset_in_std"};
    catalog.limits.push_back(
        {file, configs->limits.name, "", {{"limits", std::move(limits)}, {"fit_checks", fit}}});
  }
  const bool real = catalog.station.kind == bench::StationKind::kReal;
  if (catalog.limits.empty() && real)
    return std::unexpected(station.string() +
                           ": a production station (kind = \"real\") offers at least one "
                           "limits file: its sessions are judged");
  catalog.no_limits = !real && (offers.no_limits || catalog.limits.empty());
  return catalog;
}

bool IsSessionName(const fs::path& sessions_dir, std::string_view name) {
  if (name.empty() || name.size() > 200 || name.front() == '.' ||
      name.find("..") != std::string_view::npos)
    return false;
  for (char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '_' || c == '-';
    if (!ok) return false;
  }
  std::error_code ec;
  return fs::is_directory(sessions_dir / std::string(name), ec);
}

std::expected<nlohmann::json, std::string> RecentSessionsFromStore(const std::string& url,
                                                                   const std::string& station,
                                                                   const fs::path& sessions_dir,
                                                                   std::size_t count) {
  auto store = results::ResultsStore::OpenExisting(url);  // the panel writes no database
  if (!store) return std::unexpected(store.error().message);
  if (*store == nullptr) return nlohmann::json::array();  // nothing stored yet
  results::SessionFilter filter;
  filter.station = station;
  filter.newest = count;
  auto rows = (*store)->Sessions(filter);
  if (!rows) return std::unexpected(rows.error().message);
  std::error_code here_error;
  const fs::path here = fs::weakly_canonical(sessions_dir, here_error);
  nlohmann::json out = nlohmann::json::array();
  for (auto it = rows->rbegin(); it != rows->rend(); ++it) {
    const fs::path folder(it->path);
    const std::string name = folder.filename().string();
    std::error_code ec;
    const fs::path parent = fs::weakly_canonical(folder.parent_path(), ec);
    const bool ours = !here_error && !ec && parent == here && IsSessionName(sessions_dir, name);
    out.push_back({{"name", name},
                   {"unit", it->serial},
                   {"station", it->station},
                   {"outcome", it->outcome},
                   {"reason", it->reason},
                   {"started", it->started_utc},
                   {"report", ours && HasReport(folder)
                                  ? nlohmann::json("sessions/" + name + "/report/report.html")
                                  : nlohmann::json(nullptr)}});
  }
  return out;
}

nlohmann::json RecentSessions(const fs::path& sessions_dir, std::size_t count) {
  struct Found {
    fs::file_time_type time;
    fs::path dir;
  };
  std::vector<Found> found;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(sessions_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_directory(ec) || !IsSessionName(sessions_dir, name)) continue;
    const fs::path json = entry.path() / "session.json";
    const auto time = fs::last_write_time(json, ec);
    if (ec) continue;
    found.push_back({time, entry.path()});
  }
  std::sort(found.begin(), found.end(),
            [](const Found& a, const Found& b) { return a.time > b.time; });
  nlohmann::json out = nlohmann::json::array();
  for (const Found& f : found) {
    if (out.size() >= count) break;
    // Through the one reader of the record: a damaged or half-written one is left out of the list
    // (the operator opens it from the folder), as an unparsable file always was.
    const auto record = session::ReadSessionRecord(f.dir);
    if (!record) continue;
    const std::string name = f.dir.filename().string();
    const auto text_or_null = [](const std::string& text) {
      return text.empty() ? nlohmann::json(nullptr) : nlohmann::json(text);
    };
    nlohmann::json row;
    row["name"] = name;
    row["unit"] = record->unit_serial;
    row["station"] = text_or_null(record->station_name);
    const session::OutcomeRecord* outcome = record->outcome ? &*record->outcome : nullptr;
    row["outcome"] = outcome != nullptr
                         ? nlohmann::json(std::string(bench::ToString(outcome->kind)))
                         : nlohmann::json(nullptr);
    row["reason"] = outcome != nullptr ? nlohmann::json(outcome->reason) : nlohmann::json(nullptr);
    row["started"] = record->started ? text_or_null(record->started->utc) : nlohmann::json(nullptr);
    row["report"] = HasReport(f.dir) ? nlohmann::json("sessions/" + name + "/report/report.html")
                                     : nlohmann::json(nullptr);
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace hrgbench::app
