#pragma once
// The unit's earlier sessions for its report (report::UnitHistory), read from the station's
// results store: what hrg-bench puts in every report after the upload, and hrg-report with
// --results. The report itself opens no database.

#include <filesystem>
#include <optional>
#include <string>

#include "hrgbench/report/session_report.hpp"

namespace hrgbench::app {

// `url` empty: nullopt (no store, no section). Otherwise the sessions of the unit recorded in
// `session_dir` (its serial), oldest first, without that session itself; a store or a session that
// cannot be read gives a history with `unavailable` saying why (the report says so, and a warning
// is logged). Never throws except std::bad_alloc.
std::optional<report::UnitHistory> ReadUnitHistory(const std::string& url,
                                                   const std::filesystem::path& session_dir);

}  // namespace hrgbench::app
