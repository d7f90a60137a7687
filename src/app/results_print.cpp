#include "app/results_print.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>

namespace hrgbench::app {
namespace {

// What history shows per session: the quantities a line looks at first.
constexpr const char* kHistoryQuantities[] = {"tau_s", "q_factor", "damping_split_per_s",
                                              "frequency_split_mhz", "angular_gain"};

nlohmann::json SessionJson(const results::SessionSummary& s) {
  return {{"id", s.id},
          {"serial", s.serial},
          {"station", s.station},
          {"operator", s.operator_name},
          {"software_version", s.software_version},
          {"started_utc", s.started_utc},
          {"ended_utc", s.ended_utc},
          {"outcome", s.outcome},
          {"reason", s.reason},
          {"exit_code", s.exit_code},
          {"complete_runs", s.complete_runs},
          {"path", s.path},
          {"content_sha256", s.content_sha256}};
}

std::optional<double> Find(const std::map<std::string, double>& values, const std::string& name) {
  const auto it = values.find(name);
  return it == values.end() ? std::nullopt : std::optional<double>(it->second);
}

std::string Short(std::optional<double> v) {
  if (!v) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", *v);
  return text;
}

}  // namespace

std::string CsvField(const std::string& text) {
  bool quote = text.find_first_of(",\"\r\n") != std::string::npos;
  std::string body = text;
  if (!text.empty() && (text[0] == '=' || text[0] == '+' || text[0] == '-' || text[0] == '@') &&
      (text.size() == 1 ||
       !(std::isdigit(static_cast<unsigned char>(text[1])) || text[1] == '.'))) {
    body = "'" + text;  // shown as text, not evaluated
    quote = true;
  }
  if (!quote) return body;
  std::string out = "\"";
  for (char c : body) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string NumberText(std::optional<double> value) {
  if (!value) return "";
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, *value);
  return ec == std::errc() ? std::string(buffer, end) : std::string();
}

void PrintSessions(std::ostream& out, const std::vector<results::SessionSummary>& sessions,
                   OutputFormat format) {
  if (format == OutputFormat::kJson) {
    nlohmann::json all = nlohmann::json::array();
    for (const auto& s : sessions) all.push_back(SessionJson(s));
    out << all.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
    return;
  }
  if (format == OutputFormat::kCsv) {
    out << "id,serial,station,operator,software_version,started_utc,ended_utc,outcome,exit_code,"
           "complete_runs,reason,path\n";
    for (const auto& s : sessions) {
      out << s.id << ',' << CsvField(s.serial) << ',' << CsvField(s.station) << ','
          << CsvField(s.operator_name) << ',' << CsvField(s.software_version) << ','
          << CsvField(s.started_utc) << ',' << CsvField(s.ended_utc) << ',' << s.outcome << ','
          << s.exit_code << ',' << s.complete_runs << ',' << CsvField(s.reason) << ','
          << CsvField(s.path) << '\n';
    }
    return;
  }
  char line[512];
  std::snprintf(line, sizeof line, "%-27s %-16s %-12s %-8s %4s  %s\n", "started (UTC)", "serial",
                "station", "outcome", "runs", "reason");
  out << line;
  for (const auto& s : sessions) {
    std::snprintf(line, sizeof line, "%-27s %-16s %-12s %-8s %4d  %s\n", s.started_utc.c_str(),
                  s.serial.c_str(), s.station.c_str(), s.outcome.c_str(), s.complete_runs,
                  s.reason.c_str());
    out << line;
  }
  out << sessions.size() << " session(s)\n";
}

void PrintHistory(std::ostream& out, const std::string& serial,
                  const std::vector<results::SessionWithParameters>& sessions,
                  OutputFormat format) {
  if (format == OutputFormat::kJson) {
    nlohmann::json all = nlohmann::json::array();
    for (const auto& s : sessions) {
      nlohmann::json j = SessionJson(s.session);
      j["values"] = s.values;
      all.push_back(std::move(j));
    }
    out << all.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
    return;
  }
  if (format == OutputFormat::kCsv) {
    out << "started_utc,station,outcome";
    for (const char* q : kHistoryQuantities) out << ',' << q;
    out << ",id\n";
    for (const auto& s : sessions) {
      out << CsvField(s.session.started_utc) << ',' << CsvField(s.session.station) << ','
          << s.session.outcome;
      for (const char* q : kHistoryQuantities) out << ',' << NumberText(Find(s.values, q));
      out << ',' << s.session.id << '\n';
    }
    return;
  }
  out << "unit " << serial << ": " << sessions.size() << " session(s)\n";
  char line[512];
  std::snprintf(line, sizeof line, "%-27s %-12s %-8s %12s %12s %14s %14s %12s\n", "started (UTC)",
                "station", "outcome", "tau_s", "q_factor", "damp_split/s", "freq_split_mHz",
                "angular_gain");
  out << line;
  for (const auto& s : sessions) {
    std::snprintf(line, sizeof line, "%-27s %-12s %-8s %12s %12s %14s %14s %12s\n",
                  s.session.started_utc.c_str(), s.session.station.c_str(),
                  s.session.outcome.c_str(), Short(Find(s.values, "tau_s")).c_str(),
                  Short(Find(s.values, "q_factor")).c_str(),
                  Short(Find(s.values, "damping_split_per_s")).c_str(),
                  Short(Find(s.values, "frequency_split_mhz")).c_str(),
                  Short(Find(s.values, "angular_gain")).c_str());
    out << line;
  }
}

void PrintStats(std::ostream& out, const results::ParameterStats& st, OutputFormat format) {
  if (format == OutputFormat::kJson) {
    // One object; a number that is not determined (no sessions, no limit, no verdict) is null.
    const auto value = [&](std::optional<double> v) {
      return v && std::isfinite(*v) ? nlohmann::json(*v) : nlohmann::json();
    };
    const auto sample = [&](double v) { return st.n > 0 ? value(v) : nlohmann::json(); };
    nlohmann::json weeks = nlohmann::json::array();
    for (const auto& w : st.weeks)
      weeks.push_back(
          {{"week", w.week}, {"n", w.n}, {"mean", value(w.mean)}, {"std", value(w.std)}});
    const nlohmann::json all = {{"name", st.name},
                                {"unit", st.unit},
                                {"n", st.n},
                                {"mean", sample(st.mean)},
                                {"std", sample(st.std)},
                                {"min", sample(st.min)},
                                {"max", sample(st.max)},
                                {"limit_min", value(st.limit_min)},
                                {"limit_max", value(st.limit_max)},
                                {"judged", st.judged},
                                {"passed", st.passed},
                                {"yield", value(st.yield)},
                                {"cp", value(st.cp)},
                                {"cpk", value(st.cpk)},
                                {"weeks", std::move(weeks)}};
    out << all.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
    return;
  }
  if (format == OutputFormat::kCsv) {
    out << "period,n,mean,std,min,max,limit_min,limit_max,yield,cp,cpk\n";
    out << "all," << st.n << ',' << NumberText(st.mean) << ',' << NumberText(st.std) << ','
        << NumberText(st.min) << ',' << NumberText(st.max) << ',' << NumberText(st.limit_min) << ','
        << NumberText(st.limit_max) << ',' << NumberText(st.yield) << ',' << NumberText(st.cp)
        << ',' << NumberText(st.cpk) << '\n';
    for (const auto& w : st.weeks) {
      out << w.week << ',' << w.n << ',' << NumberText(w.mean) << ',' << NumberText(w.std)
          << ",,,,,,,\n";
    }
    return;
  }
  out << st.name << (st.unit.empty() ? "" : " [" + st.unit + "]") << ": n = " << st.n << '\n';
  if (st.n == 0) return;
  out << "  mean " << Short(st.mean) << "  std " << Short(st.std) << "  min " << Short(st.min)
      << "  max " << Short(st.max) << '\n';
  out << "  limits in force [" << Short(st.limit_min) << ", " << Short(st.limit_max) << "]  yield "
      << (st.yield ? Short(*st.yield * 100.0) + " % (" + std::to_string(st.passed) + "/" +
                         std::to_string(st.judged) + ")"
                   : std::string("- (not judged)"))
      << "  Cp " << Short(st.cp) << "  Cpk " << Short(st.cpk) << '\n';
  out << "  per week:\n";
  for (const auto& w : st.weeks) {
    out << "    " << w.week << "  n " << w.n << "  mean " << Short(w.mean) << "  std "
        << Short(w.std) << '\n';
  }
}

void PrintExport(std::ostream& out, const std::vector<results::SessionWithParameters>& sessions) {
  std::set<std::string> names;
  for (const auto& s : sessions)
    for (const auto& [name, value] : s.values) names.insert(name);
  out << "id,serial,station,operator,software_version,started_utc,ended_utc,outcome,exit_code,"
         "complete_runs,path";
  for (const std::string& name : names) out << ',' << CsvField(name);
  out << '\n';
  for (const auto& s : sessions) {
    const auto& x = s.session;
    out << x.id << ',' << CsvField(x.serial) << ',' << CsvField(x.station) << ','
        << CsvField(x.operator_name) << ',' << CsvField(x.software_version) << ','
        << CsvField(x.started_utc) << ',' << CsvField(x.ended_utc) << ',' << x.outcome << ','
        << x.exit_code << ',' << x.complete_runs << ',' << CsvField(x.path);
    for (const std::string& name : names) out << ',' << NumberText(Find(s.values, name));
    out << '\n';
  }
}

}  // namespace hrgbench::app
