#include "app/line_view.hpp"

#include <cstdio>
#include <map>

#include "hrgbench/report/html_escape.hpp"

namespace hrgbench::app {
namespace {

struct Tally {
  int sessions = 0, pass = 0, fail = 0, other = 0, first_judged = 0, first_passed = 0;
  void Add(const results::SessionSummary& s) {
    ++sessions;
    const bool judged = s.outcome == "PASS" || s.outcome == "FAIL";
    if (s.outcome == "PASS") ++pass;
    if (s.outcome == "FAIL") ++fail;
    if (!judged) ++other;
    if (judged && s.attempt == 1) {
      ++first_judged;
      if (s.outcome == "PASS") ++first_passed;
    }
  }
  nlohmann::json Json() const {
    const auto share = [](int part, int whole) {
      return whole > 0 ? nlohmann::json(static_cast<double>(part) / whole) : nlohmann::json();
    };
    return {{"sessions", sessions},
            {"pass", pass},
            {"fail", fail},
            {"other", other},
            {"yield", share(pass, pass + fail)},
            {"first_pass_judged", first_judged},
            {"first_pass_passed", first_passed},
            {"first_pass_yield", share(first_passed, first_judged)}};
  }
};

std::string Text(const nlohmann::json& value) {
  return value.is_string() ? value.get<std::string>() : value.is_null() ? "" : value.dump();
}

std::string Percent(const nlohmann::json& share) {
  if (!share.is_number()) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %%", share.get<double>() * 100.0);
  return text;
}

}  // namespace

nlohmann::json LineViewJson(const std::string& day,
                            const std::vector<results::SessionSummary>& latest,
                            const std::vector<results::SessionSummary>& today) {
  nlohmann::json stations = nlohmann::json::array();
  for (const auto& s : latest) {
    stations.push_back({{"station", s.station},
                        {"serial", s.serial},
                        {"started_utc", s.started_utc},
                        {"outcome", s.outcome},
                        {"reason", s.reason},
                        {"attempt", s.attempt},
                        {"sequence", s.sequence_name},
                        {"fixture_position", s.fixture_position}});
  }
  Tally line;
  std::map<std::string, Tally> per_station;
  for (const auto& s : today) {
    line.Add(s);
    per_station[s.station].Add(s);
  }
  nlohmann::json today_json = line.Json();
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& [station, tally] : per_station) {
    nlohmann::json row = tally.Json();
    row["station"] = station;
    rows.push_back(std::move(row));
  }
  today_json["per_station"] = std::move(rows);
  return {{"day", day}, {"stations", std::move(stations)}, {"today", std::move(today_json)}};
}

std::string LineViewHtml(const nlohmann::json& view, const std::string& store) {
  const nlohmann::json& today = view["today"];
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
      "<meta http-equiv=\"refresh\" content=\"30\"><title>Line view</title><style>"
      "body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse;margin:1em 0}"
      "td,th{border:1px solid #999;padding:.3em .6em;text-align:left}"
      ".PASS{background:#c8f0c8}.FAIL{background:#f4c0c0}.ERROR,.ABORTED{background:#f4e0a0}"
      "</style></head><body>\n<h1>Line view</h1>\n<p>Read-only, from <code>" +
      report::HtmlEscape(store) + "</code>; day <span id=\"day\">" +
      report::HtmlEscape(Text(view["day"])) + "</span> (UTC). Refreshes every 30 s.</p>\n";
  html += "<h2>Yield today</h2>\n<p id=\"line-yield\">" + Percent(today["yield"]) + " (" +
          std::to_string(today["pass"].get<int>()) + " PASS of " +
          std::to_string(today["pass"].get<int>() + today["fail"].get<int>()) +
          " judged; first pass " + Percent(today["first_pass_yield"]) + "; " +
          std::to_string(today["sessions"].get<int>()) + " sessions)</p>\n";
  html +=
      "<table id=\"yield\"><tr><th>station</th><th>sessions</th><th>PASS</th><th>FAIL</th>"
      "<th>other</th><th>yield</th><th>first-pass yield</th></tr>\n";
  for (const auto& row : today["per_station"]) {
    html += "<tr data-station=\"" + report::HtmlEscape(Text(row["station"])) + "\"><td>" +
            report::HtmlEscape(Text(row["station"])) + "</td><td>" + Text(row["sessions"]) +
            "</td><td>" + Text(row["pass"]) + "</td><td>" + Text(row["fail"]) + "</td><td>" +
            Text(row["other"]) + "</td><td class=\"yield\">" + Percent(row["yield"]) + "</td><td>" +
            Percent(row["first_pass_yield"]) + "</td></tr>\n";
  }
  html +=
      "</table>\n<h2>Stations: last session</h2>\n<table id=\"stations\"><tr><th>station</th>"
      "<th>serial</th><th>position</th><th>started (UTC)</th><th>sequence</th><th>pass</th>"
      "<th>outcome</th><th>reason</th></tr>\n";
  for (const auto& s : view["stations"]) {
    const std::string outcome = report::HtmlEscape(Text(s["outcome"]));
    html += "<tr data-station=\"" + report::HtmlEscape(Text(s["station"])) + "\"><td>" +
            report::HtmlEscape(Text(s["station"])) + "</td><td>" +
            report::HtmlEscape(Text(s["serial"])) + "</td><td>" +
            report::HtmlEscape(Text(s["fixture_position"])) + "</td><td>" +
            report::HtmlEscape(Text(s["started_utc"])) + "</td><td>" +
            report::HtmlEscape(Text(s["sequence"])) + "</td><td>" +
            (s["attempt"].get<int>() <= 1 ? std::string("first")
                                          : "retest " + std::to_string(s["attempt"].get<int>())) +
            "</td><td class=\"outcome " + outcome + "\">" + outcome + "</td><td>" +
            report::HtmlEscape(Text(s["reason"])) + "</td></tr>\n";
  }
  html += "</table>\n</body></html>\n";
  return html;
}

}  // namespace hrgbench::app
