#pragma once
// The line view (hrg-results serve, issue 26 §3): every station's last session and the line's
// yield today, read from the line's results store, as a read-only page. The page is rendered by
// the server (no script: it works in any browser on the line and shows what the store held when it
// was asked); /api/line gives the same as JSON. Pure formatting; thread-safe.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/results/results_store.hpp"

namespace hrgbench::app {

// {"day": "2026-11-26", "stations": [{station, serial, started_utc, outcome, reason, attempt,
// sequence, fixture_position}], "today": {"sessions", "pass", "fail", "other", "yield",
// "first_pass_judged", "first_pass_passed", "first_pass_yield", "per_station": [...]}}. Yield: PASS
// over PASS + FAIL (an ERROR or ABORTED session says nothing about the unit); null when none.
nlohmann::json LineViewJson(const std::string& day,
                            const std::vector<results::SessionSummary>& latest,
                            const std::vector<results::SessionSummary>& today);

// The page of that JSON (every text escaped).
std::string LineViewHtml(const nlohmann::json& view, const std::string& store);

}  // namespace hrgbench::app

namespace hrgbench::app {

// Serves the line view of the store at `url` on 127.0.0.1:`port` (0: any free port) until SIGINT
// or SIGTERM: GET / (the page) and GET /api/line (the JSON); any other method or path is refused.
// Each request opens the store read-only (OpenExisting), so the page is never older than the
// request and the server writes nothing. `day` ("YYYY-MM-DD", UTC) fixes "today" for a test; ""
// is the current UTC day. Prints "line view: http://127.0.0.1:PORT/" once listening. Exit code.
int ServeLineView(const std::string& url, int port, const std::string& day);

}  // namespace hrgbench::app
