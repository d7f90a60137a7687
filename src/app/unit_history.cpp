#include "app/unit_history.hpp"

#include <spdlog/spdlog.h>

#include "hrgbench/results/results_store.hpp"
#include "hrgbench/results/session_row.hpp"

namespace hrgbench::app {
namespace {

report::UnitHistory Unavailable(report::UnitHistory history, std::string why) {
  spdlog::warn("report: the unit's earlier sessions are not available: {}", why);
  history.unavailable = std::move(why);
  return history;
}

}  // namespace

std::optional<report::UnitHistory> ReadUnitHistory(const std::string& url,
                                                   const std::filesystem::path& session_dir) {
  if (url.empty()) return std::nullopt;
  report::UnitHistory history;
  history.store = url;
  // The serial and the stable id as the store knows them (an unfinished session has neither).
  const auto record = results::ReadSessionRow(session_dir);
  if (!record) return Unavailable(std::move(history), record.error());
  auto store = results::ResultsStore::OpenExisting(url);  // a report writes no database
  if (!store) return Unavailable(std::move(history), store.error().message);
  if (*store == nullptr) return history;  // nothing stored yet
  results::SessionFilter filter;
  filter.serial = record->serial;
  // The export rows: each parameter with its std (the trend plots' bars), not only its value.
  auto sessions = (*store)->ExportRows(filter);
  if (!sessions) return Unavailable(std::move(history), sessions.error().message);
  for (results::SessionExport& s : *sessions) {
    if (s.session.id == record->id) continue;
    report::UnitHistoryEntry entry;
    entry.started_utc = std::move(s.session.started_utc);
    entry.station = std::move(s.session.station);
    entry.outcome = std::move(s.session.outcome);
    entry.path = std::move(s.session.path);
    for (const auto& [name, row] : s.parameters) {
      if (row.value) entry.values[name] = *row.value;
      if (row.std) entry.stds[name] = *row.std;
    }
    history.sessions.push_back(std::move(entry));
  }
  return history;
}

}  // namespace hrgbench::app
