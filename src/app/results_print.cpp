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
          {"sequence", s.sequence_name},
          {"sequence_sha256", s.sequence_sha256},
          {"limits", s.limits_name},
          {"limits_sha256", s.limits_sha256},
          {"product", s.product},
          {"fixture_position", s.fixture_position},
          {"attempt", s.attempt},
          {"first_pass", s.attempt == 1},
          {"started_utc", s.started_utc},
          {"ended_utc", s.ended_utc},
          {"outcome", s.outcome},
          {"reason", s.reason},
          {"exit_code", s.exit_code},
          {"complete_runs", s.complete_runs},
          {"path", s.path},
          {"content_sha256", s.content_sha256}};
}

// "first" or "retest N" (the N-th session of the unit with its sequence).
std::string Pass(int attempt) {
  return attempt <= 1 ? "first" : "retest " + std::to_string(attempt);
}

// Columns of a text table: each cell cut to its width (Cell), padded, separated by a space.
std::string Row(const std::vector<std::pair<std::string, std::size_t>>& cells) {
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const auto& [text, width] = cells[i];
    std::string cell = Cell(text, width);
    if (i + 1 < cells.size()) {
      std::size_t shown = 0;
      for (unsigned char c : cell) shown += (c & 0xC0) != 0x80 ? 1 : 0;
      cell.append(width > shown ? width - shown : 0, ' ');
      cell += ' ';
    }
    line += cell;
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line + '\n';
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

constexpr const char* kSessionCsvHeader =
    "id,serial,station,operator,software_version,sequence,sequence_sha256,limits,limits_sha256,"
    "product,fixture_position,attempt,first_pass,started_utc,ended_utc,outcome,exit_code,"
    "complete_runs";

}  // namespace

std::string SessionCsvHeader() { return kSessionCsvHeader; }

std::string SessionCsvFields(const results::SessionSummary& s) {
  return s.id + ',' + CsvField(s.serial) + ',' + CsvField(s.station) + ',' +
         CsvField(s.operator_name) + ',' + CsvField(s.software_version) + ',' +
         CsvField(s.sequence_name) + ',' + s.sequence_sha256 + ',' + CsvField(s.limits_name) + ',' +
         s.limits_sha256 + ',' + CsvField(s.product) + ',' + CsvField(s.fixture_position) + ',' +
         std::to_string(s.attempt) + ',' + (s.attempt == 1 ? "true" : "false") + ',' +
         CsvField(s.started_utc) + ',' + CsvField(s.ended_utc) + ',' + s.outcome + ',' +
         std::to_string(s.exit_code) + ',' + std::to_string(s.complete_runs);
}

std::string Cell(const std::string& text, std::size_t width) {
  std::string flat;
  for (char c : text) flat += c == '\n' || c == '\r' || c == '\t' ? ' ' : c;
  // Code points, counted by their lead bytes; a cut never splits one.
  std::size_t points = 0, cut = flat.size(), keep = std::string::npos;
  for (std::size_t i = 0; i < flat.size(); ++i) {
    if ((static_cast<unsigned char>(flat[i]) & 0xC0) == 0x80) continue;
    if (points + 1 == width) keep = i;  // where "…" goes if the text is too long
    if (points == width) {
      cut = i;
      break;
    }
    ++points;
  }
  if (cut == flat.size()) return flat;
  if (width == 0) return "";
  return flat.substr(0, keep) + "\u2026";
}

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
    out << SessionCsvHeader() << ",reason,path\n";
    for (const auto& s : sessions)
      out << SessionCsvFields(s) << ',' << CsvField(s.reason) << ',' << CsvField(s.path) << '\n';
    return;
  }
  // Every cell cut to its column (Cell): one session, one line, whatever its reason holds.
  out << Row({{"started (UTC)", 27},
              {"serial", 16},
              {"station", 12},
              {"sequence", 12},
              {"pos", 3},
              {"pass", 9},
              {"outcome", 7},
              {"runs", 4},
              {"reason", 60}});
  for (const auto& s : sessions) {
    out << Row({{s.started_utc, 27},
                {s.serial, 16},
                {s.station, 12},
                {s.sequence_name, 12},
                {s.fixture_position.empty() ? "-" : s.fixture_position, 3},
                {Pass(s.attempt), 9},
                {s.outcome, 7},
                {std::to_string(s.complete_runs), 4},
                {s.reason, 60}});
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
  out << Row({{"started (UTC)", 27},
              {"station", 12},
              {"pass", 9},
              {"outcome", 8},
              {"tau_s", 12},
              {"q_factor", 12},
              {"damp_split/s", 14},
              {"freq_split_mHz", 14},
              {"angular_gain", 12}});
  for (const auto& s : sessions) {
    out << Row({{s.session.started_utc, 27},
                {s.session.station, 12},
                {Pass(s.session.attempt), 9},
                {s.session.outcome, 8},
                {Short(Find(s.values, "tau_s")), 12},
                {Short(Find(s.values, "q_factor")), 12},
                {Short(Find(s.values, "damping_split_per_s")), 14},
                {Short(Find(s.values, "frequency_split_mhz")), 14},
                {Short(Find(s.values, "angular_gain")), 12}});
  }
}

void PrintStats(std::ostream& out, const std::vector<results::GroupBy>& by,
                const std::vector<GroupStats>& groups, OutputFormat format) {
  const auto value = [](std::optional<double> v) {
    return v && std::isfinite(*v) ? nlohmann::json(*v) : nlohmann::json();
  };
  if (format == OutputFormat::kJson) {
    // One object per group; a number that is not determined (no sessions, no limit, no verdict)
    // is null. Without --by: the one group's object alone.
    nlohmann::json all = nlohmann::json::array();
    for (const GroupStats& g : groups) {
      const results::ParameterStats& st = g.stats;
      const auto sample = [&](double v) { return st.n > 0 ? value(v) : nlohmann::json(); };
      nlohmann::json weeks = nlohmann::json::array();
      for (const auto& w : st.weeks)
        weeks.push_back(
            {{"week", w.week}, {"n", w.n}, {"mean", value(w.mean)}, {"std", value(w.std)}});
      nlohmann::json j = {{"name", st.name},
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
                          {"first_pass_judged", st.first_pass_judged},
                          {"first_pass_passed", st.first_pass_passed},
                          {"first_pass_yield", value(st.first_pass_yield)},
                          {"capability", st.capability},
                          {"cp", value(st.cp)},
                          {"cpk", value(st.cpk)},
                          {"cpu", value(st.cpu)},
                          {"cpl", value(st.cpl)},
                          {"weeks", std::move(weeks)}};
      if (!by.empty()) {
        nlohmann::json key = nlohmann::json::object();
        for (std::size_t i = 0; i < by.size(); ++i) key[results::ToString(by[i])] = g.key[i];
        j["group"] = std::move(key);
      }
      all.push_back(std::move(j));
    }
    const nlohmann::json& shown = by.empty() && all.size() == 1 ? all[0] : all;
    out << shown.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
    return;
  }
  if (format == OutputFormat::kCsv) {
    for (results::GroupBy b : by) out << results::ToString(b) << ',';
    out << "period,n,mean,std,min,max,unit,limit_min,limit_max,judged,passed,yield,"
           "first_pass_judged,first_pass_passed,first_pass_yield,capability,cp,cpk,cpu,cpl\n";
    for (const GroupStats& g : groups) {
      const results::ParameterStats& st = g.stats;
      std::string key;
      for (const std::string& k : g.key) key += CsvField(k) + ',';
      out << key << "all," << st.n << ',' << NumberText(st.mean) << ',' << NumberText(st.std) << ','
          << NumberText(st.min) << ',' << NumberText(st.max) << ',' << CsvField(st.unit) << ','
          << NumberText(st.limit_min) << ',' << NumberText(st.limit_max) << ',' << st.judged << ','
          << st.passed << ',' << NumberText(st.yield) << ',' << st.first_pass_judged << ','
          << st.first_pass_passed << ',' << NumberText(st.first_pass_yield) << ',' << st.capability
          << ',' << NumberText(st.cp) << ',' << NumberText(st.cpk) << ',' << NumberText(st.cpu)
          << ',' << NumberText(st.cpl) << '\n';
      for (const auto& w : st.weeks) {
        out << key << w.week << ',' << w.n << ',' << NumberText(w.mean) << ',' << NumberText(w.std)
            << ",,,,,,,,,,,,,,,,\n";
      }
    }
    return;
  }
  for (const GroupStats& g : groups) {
    const results::ParameterStats& st = g.stats;
    out << st.name << " [" << (st.unit.empty() ? "?" : st.unit) << "]";
    for (std::size_t i = 0; i < by.size(); ++i) {
      out << (i == 0 ? "  " : ", ") << results::ToString(by[i]) << " "
          << (g.key[i].empty() ? "(none)" : "'" + Cell(g.key[i], 40) + "'");
    }
    out << ": n = " << st.n << '\n';
    if (st.n == 0) continue;
    out << "  mean " << Short(st.mean) << "  std " << Short(st.std) << "  min " << Short(st.min)
        << "  max " << Short(st.max) << '\n';
    const auto yield = [](std::optional<double> y, std::size_t passed, std::size_t judged) {
      return y ? Short(*y * 100.0) + " % (" + std::to_string(passed) + "/" +
                     std::to_string(judged) + ")"
               : std::string("- (not judged)");
    };
    out << "  limits in force [" << Short(st.limit_min) << ", " << Short(st.limit_max)
        << "]  yield " << yield(st.yield, st.passed, st.judged) << "  first-pass yield "
        << yield(st.first_pass_yield, st.first_pass_passed, st.first_pass_judged) << '\n';
    out << "  capability ";
    if (st.capability == "Cpk") {
      out << "Cp " << Short(st.cp) << "  Cpk " << Short(st.cpk) << " (two-sided)";
    } else if (st.capability == "Cpu") {
      out << "Cpu " << Short(st.cpu) << " (one-sided: upper limit only"
          << (st.limit_min ? "; 0 is the magnitude's natural bound" : "") << ")";
    } else if (st.capability == "Cpl") {
      out << "Cpl " << Short(st.cpl) << " (one-sided: lower limit only)";
    } else {
      out << "- (" << (st.limit_min || st.limit_max ? "no spread" : "no limit in force") << ")";
    }
    out << '\n';
    out << "  per week:\n";
    for (const auto& w : st.weeks) {
      out << "    " << w.week << "  n " << w.n << "  mean " << Short(w.mean) << "  std "
          << Short(w.std) << '\n';
    }
  }
}

void PrintExport(std::ostream& out, const std::vector<results::SessionExport>& sessions) {
  std::set<std::string> names;
  for (const auto& s : sessions) {
    for (const auto& [name, row] : s.parameters) names.insert(name);
    for (const auto& [name, row] : s.limits) names.insert(name);
  }
  out << SessionCsvHeader() << ",reason,path";
  for (const std::string& name : names) {
    const std::string n = CsvField(name);
    out << ',' << n << ',' << n << "_std," << n << "_unit," << n << "_limit_min," << n
        << "_limit_max," << n << "_status," << n << "_message";
  }
  out << '\n';
  for (const auto& s : sessions) {
    out << SessionCsvFields(s.session) << ',' << CsvField(s.session.reason) << ','
        << CsvField(s.session.path);
    for (const std::string& name : names) {
      const auto p = s.parameters.find(name);
      const auto l = s.limits.find(name);
      const bool has_p = p != s.parameters.end(), has_l = l != s.limits.end();
      // The verdict's value when no parameter row holds one (a verdict on a quantity the
      // estimate left undetermined).
      out << ',' << NumberText(has_p ? p->second.value : (has_l ? l->second.value : std::nullopt))
          << ',' << NumberText(has_p ? p->second.std : (has_l ? l->second.std : std::nullopt))
          << ',' << (has_p ? CsvField(p->second.unit) : "") << ','
          << NumberText(has_l ? l->second.min : std::nullopt) << ','
          << NumberText(has_l ? l->second.max : std::nullopt) << ','
          << (has_l ? CsvField(l->second.status) : "") << ','
          << (has_l ? CsvField(l->second.message) : "");
    }
    out << '\n';
  }
}

}  // namespace hrgbench::app
