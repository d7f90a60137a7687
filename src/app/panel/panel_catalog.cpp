#include "app/panel/panel_catalog.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "hrgbench/results/results_store.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

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
  const fs::path dir = station.parent_path().empty() ? fs::path(".") : station.parent_path();
  for (const fs::path& file : Matching(dir, "sequence-")) {
    auto configs = bench::LoadBenchConfigs(station, file, {});
    if (!configs) {
      spdlog::warn("panel: {} not offered: {}", file.string(), configs.error().ToString());
      continue;
    }
    const bench::SequenceConfig& seq = configs->sequence;
    char text[160];
    std::snprintf(text, sizeof text, "%zu runs, %.0f s of free run", seq.runs.size(),
                  seq.TotalFreeRunS());
    catalog.sequences.push_back({file, seq.name, text});
  }
  for (const fs::path& file : Matching(dir, "limits-")) {
    if (catalog.sequences.empty()) break;
    auto configs = bench::LoadBenchConfigs(station, catalog.sequences.front().file, file);
    if (!configs) {
      spdlog::warn("panel: {} not offered: {}", file.string(), configs.error().ToString());
      continue;
    }
    catalog.limits.push_back({file, configs->limits.name, ""});
  }
  if (catalog.sequences.empty())
    return std::unexpected("no sequence-*.toml beside " + station.string() +
                           " loads with it: the panel has nothing to offer");
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
                   {"report", ours && fs::exists(folder / "report" / "report.html", ec)
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
    row["report"] = fs::exists(f.dir / "report" / "report.html", ec)
                        ? nlohmann::json("sessions/" + name + "/report/report.html")
                        : nlohmann::json(nullptr);
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace hrgbench::app
