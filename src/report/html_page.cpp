#include "html_page.hpp"

#include <cctype>
#include <map>
#include <string>
#include <vector>

#include "html_text.hpp"
#include "page.hpp"
#include "page_script.hpp"
#include "report_data.hpp"

namespace hrgbench::report::internal {

using nlohmann::json;

void Page::Head() {
  out_ +=
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>HRG session "
      "report " +
      Text("/unit/serial") +
      "</title>\n<style>\n"
      "body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1000px;color:#222}\n"
      "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 6px;"
      "text-align:left;vertical-align:top}th{background:#f2f2f2}\n"
      ".num{font-variant-numeric:tabular-nums}.na{color:#888}\n"
      "#outcome{font-size:1.6em;font-weight:bold;padding:.5em .8em;border-radius:6px;color:#fff;"
      "margin:.8em 0}\n"
      "#outcome[data-kind=PASS]{background:#1b7f3b}#outcome[data-kind=FAIL]{background:#b3261e}"
      "#outcome:not([data-kind=PASS]):not([data-kind=FAIL]){background:#b26a00}\n"
      "#outcome .reason{font-size:.6em;font-weight:normal;display:block}\n"
      "li.warning{color:#8a4b00}\nfigure{margin:1em 0;page-break-inside:avoid}"
      "canvas{max-width:100%}figcaption{font-size:.9em;color:#444}\n"
      "section.run{border-top:2px solid #888;margin-top:2em;page-break-before:always}\n"
      ".status-FAIL{color:#b3261e;font-weight:bold}.status-PASS{color:#1b7f3b}\n"
      "</style>\n</head>\n<body>\n";
}

void Page::Meta() {
  out_ +=
      "<h1>HRG session report: unit " + Text("/unit/serial") + "</h1>\n<table class=\"meta\">\n";
  const auto row = [&](const char* name, const std::string& value) {
    out_ += std::string("<tr><th>") + name + "</th><td>" + value + "</td></tr>\n";
  };
  row("unit serial", Text("/unit/serial"));
  row("station", Has("/station/name") ? Text("/station/name") : kMissing);
  row("software version",
      Has("/software/version") ? Text("/software/version") : Text("/software_version"));
  if (Has("/config_sha256")) {
    for (const char* key : {"station", "sequence", "limits"})
      row((std::string("config sha256: ") + key).c_str(),
          Text(std::string("/config_sha256/") + key));
  } else if (Has("/spec_sha256")) {
    row("spec sha256", Text("/spec_sha256"));
  } else {
    row("config hashes", kMissing);
  }
  row("started (UTC)", Text("/started/utc"));
  row("ended (UTC)", Text("/ended/utc"));
  row("state", Text("/state"));
  if (Has("/description")) row("description", Text("/description"));
  row("session directory", HtmlEscape(in_.session_dir.string()));
  out_ += "</table>\n";
}

void Page::Outcome() {
  if (!Has("/outcome")) {
    out_ +=
        "<div id=\"outcome\" data-kind=\"NOT RECORDED\">NOT RECORDED<span class=\"reason\">"
        "session.json has no outcome (a session from hrg-sim, an older format, or one that did "
        "not close); the estimate below is the report's own</span></div>\n";
    return;
  }
  const json* kind = At(doc_, "/outcome/kind");
  const std::string k = kind != nullptr && kind->is_string() ? kind->get<std::string>() : "UNKNOWN";
  out_ += "<div id=\"outcome\" data-kind=\"" + Attr(k) + "\">" + HtmlEscape(k) +
          "<span class=\"reason\">" + Text("/outcome/reason") + " (exit code " +
          Src("/outcome/exit_code") + ")</span></div>\n";
  const std::size_t failed = Size(doc_, "/outcome/failed_parameters");
  if (failed > 0) {
    out_ += "<p>Out of limits:</p><ul>";
    for (std::size_t i = 0; i < failed; ++i) {
      const std::string p = "/outcome/failed_parameters/" + std::to_string(i);
      out_ += "<li>" + Text(p + "/name") + " = " + Src(p + "/value") + " (limits " +
              Src(p + "/min") + " … " + Src(p + "/max") + ")</li>";
    }
    out_ += "</ul>\n";
  }
}

void Page::Warnings(int run) {
  const auto it = warnings_by_run_.find(run);
  if (it == warnings_by_run_.end() || it->second.empty()) return;
  out_ += "<ul class=\"warnings\">\n";
  for (const std::string& w : it->second)
    out_ += "<li class=\"warning\" data-run=\"" + std::to_string(run) + "\">" + HtmlEscape(w) +
            "</li>\n";
  out_ += "</ul>\n";
}

void Page::Estimate() {
  const bool recorded = Has("/outcome/estimate/delta");
  const std::string base = recorded ? "/outcome/estimate/" : "/derived/estimate/";
  const auto value = [&](const std::string& pointer) {
    return recorded ? Src(pointer) : Der(pointer);
  };
  out_ += "<h2>Model parameters δ and ξ</h2>\n<p>";
  out_ += recorded ? "As recorded by the bench (outcome.estimate, method " +
                         Text("/outcome/estimate/method") + ")."
                   : std::string("Not recorded in session.json: estimated by the report (ml).");
  out_ += " The Cramér–Rao bound is of the session's own design (derived by the report).</p>\n";
  std::string truth_base;
  if (Has("/outcome/estimate/truth/delta"))
    truth_base = "/outcome/estimate/truth/";
  else if (Has("/simulation/delta"))
    truth_base = "/simulation/";
  out_ +=
      "<table class=\"parameters\"><tr><th>parameter</th><th>meaning</th><th>estimate</th>"
      "<th>± std</th>";
  if (!truth_base.empty()) out_ += "<th>truth (simulated)</th><th>(estimate − truth)/std</th>";
  out_ += "<th>Cramér–Rao std</th></tr>\n";
  static const char* kMeaning[10] = {"damping δ1 [1/s]",
                                     "angular gain δ2",
                                     "damping anisotropy δ3 [1/s]",
                                     "damping anisotropy δ4 [1/s]",
                                     "frequency anisotropy δ5 [rad/s]",
                                     "frequency anisotropy δ6 [rad/s]",
                                     "gain mismatch ξ1",
                                     "phase mismatch ξ2",
                                     "cross-talk ξ3",
                                     "electrode misplacement ξ4"};
  for (int p = 0; p < 10; ++p) {
    const bool is_delta = p < 6;
    const std::string i = std::to_string(is_delta ? p : p - 6);
    const std::string key = is_delta ? "delta" : "xi";
    const auto [estimate, std_dev] =
        WithStd(!recorded, base + key + "/" + i, base + key + "_std/" + i);
    out_ += "<tr><td>" + std::string(is_delta ? "δ" : "ξ") +
            std::to_string((is_delta ? p : p - 6) + 1) + "</td><td>" + kMeaning[p] + "</td><td>" +
            estimate + "</td><td>" + std_dev + "</td>";
    const double std_value = NumberAt(recorded ? doc_ : data_, base + key + "_std/" + i);
    if (!truth_base.empty()) {
      // The truth to the estimate's precision, so the two columns read side by side.
      const std::string truth = truth_base + key + "/" + i;
      const std::string z = "/derived/truth_deviation/" + key + "/" + i;
      out_ += "<td>" + Num(false, truth, Metrological(NumberAt(doc_, truth), std_value).value) +
              "</td><td>" + Num(true, z, Fixed(NumberAt(data_, z), 2)) + "</td>";
    }
    const std::string bound = "/derived/crlb/" + key + "_std/" + i;
    out_ += "<td>" + Num(true, bound, TwoSignificant(NumberAt(data_, bound))) + "</td></tr>\n";
  }
  out_ += "</table>\n<p>Residual RMS " + value(base + "residual_rms") + ", noise σ̂ " +
          value(base + "noise_sigma") + ", " + value(base + "samples_used") + " samples, " +
          value(base + "iterations") + " iterations.</p>\n";
}

// One table of every quantity's uncertainty budget (GUM: components with their sources, the
// combined standard uncertainty and the coverage factor), largest component first as recorded.
void Page::EngineeringBudgets(const std::string& base) {
  const std::size_t n = Size(doc_, base + "/quantities");
  std::string rows;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string q = base + "/quantities/" + std::to_string(i);
    const std::size_t components = Size(doc_, q + "/budget");
    if (components == 0) continue;
    const std::string unit = Has(q + "/unit") ? Text(q + "/unit") : std::string();
    rows += "<tr class=\"budget-total\"><td rowspan=\"" + std::to_string(components + 1) + "\">" +
            (Has(q + "/label") ? Text(q + "/label") : Text(q + "/name")) +
            "</td><td>combined u<sub>c</sub></td><td></td><td>" + Src(q + "/std") + " " + unit +
            "</td><td></td></tr>\n";
    for (std::size_t c = 0; c < components; ++c) {
      const std::string b = q + "/budget/" + std::to_string(c);
      const bool evaluated = NumberAt(doc_, b + "/standard_uncertainty") ==
                             NumberAt(doc_, b + "/standard_uncertainty");  // not NaN/null
      rows += "<tr><td>" + Text(b + "/source") + "</td><td>" + Text(b + "/type") + "</td><td>" +
              (evaluated ? Src(b + "/standard_uncertainty") + " " + unit
                         : std::string("<span class=\"na\">not evaluated</span>")) +
              "</td><td>" + Text(b + "/note") + "</td></tr>\n";
    }
  }
  if (rows.empty()) return;
  out_ +=
      "<h3>Uncertainty budgets</h3>\n<p>Each quantity's components (type A: from this "
      "session's data; type B: from a model or a declaration), largest first. The verdict "
      "judges u<sub>c</sub>; the expanded uncertainty is U = " +
      Src(base + "/coverage_factor") +
      "·u<sub>c</sub>.</p>\n<table class=\"budget\"><tr><th>quantity</th><th>component</th>"
      "<th>type</th><th>standard uncertainty</th><th>how</th></tr>\n" +
      rows + "</table>\n";
  const std::size_t notes = Size(doc_, base + "/limitations");
  for (std::size_t i = 0; i < notes; ++i)
    out_ += "<p class=\"note\">" + Text(base + "/limitations/" + std::to_string(i)) + "</p>\n";
}

void Page::Engineering() {
  out_ += "<h2>The resonator in its own units</h2>\n";
  const std::string base = "/outcome/estimate/engineering";
  if (!Has(base)) {
    out_ += "<p>Engineering quantities: " + std::string(kMissing) +
            " (session.json has no outcome.estimate.engineering).</p>\n";
  } else {
    out_ += "<p>Carrier frequency " + Src(base + "/frequency_hz") + " Hz (" +
            Text(base + "/frequency_source") +
            ").</p>\n<table class=\"engineering\"><tr><th>"
            "quantity</th><th>value</th><th>± u<sub>c</sub></th><th>unit</th><th>note</th></tr>\n";
    const std::size_t n = Size(doc_, base + "/quantities");
    for (std::size_t i = 0; i < n; ++i) {
      const std::string q = base + "/quantities/" + std::to_string(i);
      const json* determined = At(doc_, q + "/determined");
      const bool ok = determined == nullptr || !determined->is_boolean() || determined->get<bool>();
      out_ += "<tr><td>" + (Has(q + "/label") ? Text(q + "/label") : Text(q + "/name")) + "</td>";
      if (ok) {
        const auto [value, std_dev] = WithStd(false, q + "/value", q + "/std");
        out_ += "<td>" + value + "</td><td>" + std_dev + "</td>";
      } else {
        out_ += "<td colspan=\"2\" class=\"na\">undetermined</td>";
      }
      out_ += "<td>" + (Has(q + "/unit") ? Text(q + "/unit") : std::string()) + "</td><td>" +
              (Has(q + "/note") ? Text(q + "/note") : std::string()) + "</td></tr>\n";
    }
    out_ += "</table>\n";
    EngineeringBudgets(base);
  }
  // The report's own anisotropy only when the record has none (the table above is the record's,
  // and says which axes are determined).
  const json* a = At(data_, "/derived/anisotropy");
  if (!Has(base) && a != nullptr && a->is_object()) {
    out_ += "<p>Anisotropy from δ (" + HtmlEscape(a->value("delta_source", "")) +
            ", derived by the report): frequency split " +
            Der("/derived/anisotropy/frequency_split_hz") + " Hz, its high-frequency axis at " +
            Der("/derived/anisotropy/frequency_axis_shell_deg") +
            "° on the shell; damping anisotropy Δ(1/τ) " +
            Der("/derived/anisotropy/damping_anisotropy_per_s") + " 1/s, its fast axis at " +
            Der("/derived/anisotropy/damping_axis_shell_deg") + "° on the shell; τ " +
            Der("/derived/anisotropy/decay_time_s") + " s.</p>\n";
  }
  Figure("anisotropy", 600, 720);
}

void Page::Verdict() {
  out_ += "<h2>Limits</h2>\n";
  const std::string base = "/outcome/verdict";
  if (!Has(base)) {
    out_ += "<p>Verdict: " + std::string(kMissing) +
            " (session.json has no outcome.verdict).</p>\n<h2>Fit checks</h2>\n<p>" + kMissing +
            "</p>\n";
    return;
  }
  out_ += "<p>Overall " + Text(base + "/overall") +
          "; the fit within its model: " + Text(base + "/fit_acceptable") + ".</p>\n";
  const std::size_t n = Size(doc_, base + "/limits");
  out_ +=
      "<table class=\"limits\"><tr><th>quantity</th><th>value</th><th>± std</th><th>min</th>"
      "<th>max</th><th>status</th><th>message</th></tr>\n";
  for (std::size_t i = 0; i < n; ++i) {
    const std::string l = base + "/limits/" + std::to_string(i);
    const json* status = At(doc_, l + "/status");
    const std::string s =
        status != nullptr && status->is_string() ? status->get<std::string>() : "";
    out_ += "<tr><td>" + Text(l + "/quantity") + "</td><td>" + Src(l + "/value") + "</td><td>" +
            Src(l + "/std") + "</td><td>" + Src(l + "/min") + "</td><td>" + Src(l + "/max") +
            "</td><td class=\"status-" + Attr(s) + "\">" + HtmlEscape(s) + "</td><td>" +
            Text(l + "/message") + "</td></tr>\n";
  }
  out_ += "</table>\n<h2>Fit checks</h2>\n";
  const std::size_t m = Size(doc_, base + "/fit_checks");
  out_ +=
      "<table class=\"fit-checks\"><tr><th>run</th><th>check</th><th>value</th><th>max</th>"
      "<th>status</th><th>message</th></tr>\n";
  for (std::size_t i = 0; i < m; ++i) {
    const std::string c = base + "/fit_checks/" + std::to_string(i);
    const json* status = At(doc_, c + "/status");
    const std::string s =
        status != nullptr && status->is_string() ? status->get<std::string>() : "";
    out_ += "<tr><td>" + Text(c + "/run") + "</td><td>" + Text(c + "/name") + "</td><td>" +
            Src(c + "/value") + "</td><td>" + Src(c + "/max") + "</td><td class=\"status-" +
            Attr(s) + "\">" + HtmlEscape(s) + "</td><td>" + Text(c + "/message") + "</td></tr>\n";
  }
  out_ += "</table>\n";
}

// The quantities a line compares across a unit's sessions (estimator/engineering_quantities.hpp).
constexpr std::pair<const char*, const char*> kHistoryColumns[] = {
    {"tau_s", "τ, s"},
    {"q_factor", "Q"},
    {"frequency_split_mhz", "Δf, mHz"},
    {"damping_split_per_s", "Δ(1/τ), 1/s"},
    {"angular_gain", "k"},
    {"gain_mismatch_percent", "g2/g1 − 1, %"},
};

void Page::UnitHistory() {
  const json* history = At(data_, "/derived/unit_history");
  if (history == nullptr || !history->is_object()) return;  // no results store configured
  out_ += "<section id=\"unit-history\">\n<h2>This unit's earlier sessions</h2>\n";
  const std::string store = history->value("store", "");
  const std::string unavailable = history->value("unavailable", "");
  if (!unavailable.empty()) {
    out_ += "<p class=\"na\">From " + HtmlEscape(store) + ": not available (" +
            HtmlEscape(unavailable) + ").</p>\n</section>\n";
    return;
  }
  const std::size_t shown = Size(data_, "/derived/unit_history/sessions");
  const std::size_t count = history->value("count", std::size_t{0});
  if (count == 0) {
    out_ += "<p>None in " + HtmlEscape(store) +
            ": this is the unit's first session there.</p>\n"
            "</section>\n";
    return;
  }
  out_ += "<p>" + std::to_string(count) + " in " + HtmlEscape(store) +
          (shown < count ? ", the latest " + std::to_string(shown) + " shown" : std::string()) +
          "; this session last.</p>\n<table class=\"unit-history\"><tr><th>started (UTC)</th>"
          "<th>station</th><th>outcome</th>";
  for (const auto& [name, label] : kHistoryColumns) out_ += "<th>" + HtmlEscape(label) + "</th>";
  out_ += "</tr>\n";
  for (std::size_t i = 0; i < shown; ++i) {
    const std::string s = "/derived/unit_history/sessions/" + std::to_string(i);
    const json& e = *At(data_, s);
    const std::string outcome = e.value("outcome", "");
    out_ += "<tr data-session=\"" + Attr(e.value("path", "")) + "\"><td>" +
            HtmlEscape(e.value("started_utc", "")) + "</td><td>" +
            HtmlEscape(e.value("station", "")) + "</td><td class=\"status-" + Attr(outcome) +
            "\">" + HtmlEscape(outcome) + "</td>";
    for (const auto& [name, label] : kHistoryColumns)
      out_ += "<td>" + Der(s + "/values/" + name) + "</td>";
    out_ += "</tr>\n";
  }
  // This session, from its own record.
  const json* recorded_kind = At(doc_, "/outcome/kind");
  const std::string kind = recorded_kind != nullptr && recorded_kind->is_string()
                               ? recorded_kind->get<std::string>()
                               : "";
  out_ += "<tr class=\"this-session\"><td>" + Text("/started/utc") + "</td><td>" +
          Text("/station/name") + "</td><td class=\"status-" + Attr(kind) + "\">" +
          HtmlEscape(kind) + " (this session)</td>";
  const std::string quantities = "/outcome/estimate/engineering/quantities";
  for (const auto& [name, label] : kHistoryColumns) {
    std::string cell = kNone;
    for (std::size_t q = 0; q < Size(doc_, quantities); ++q) {
      const std::string p = quantities + "/" + std::to_string(q);
      const json* n = At(doc_, p + "/name");
      if (n != nullptr && n->is_string() && *n == name) cell = Src(p + "/value");
    }
    out_ += "<td>" + cell + "</td>";
  }
  out_ += "</tr>\n</table>\n</section>\n";
}

void Page::Figure(const std::string& name, int width, int height) {
  const auto it = captions_.find(name);
  if (it == captions_.end()) {
    out_ += "<p class=\"na\">Figure " + HtmlEscape(name) +
            ": not drawn (nothing to draw it from).</p>\n";
    return;
  }
  out_ += "<figure><canvas data-figure=\"" + Attr(name) + "\" width=\"" + std::to_string(width) +
          "\" height=\"" + std::to_string(height) + "\"></canvas><figcaption>" +
          HtmlEscape(it->second) + "</figcaption></figure>\n";
}

std::string Page::Render(const std::string& chart_js) {
  for (const json& f : data_["figures"]) captions_[f.value("name", "")] = f.value("caption", "");
  for (const std::string& w : in_.warnings) {
    int run = WarningRun(w);
    bool known = false;
    for (const RunView& v : in_.runs) known = known || v.id == run;
    warnings_by_run_[known ? run : 0].push_back(w);
  }
  Head();
  Meta();
  Outcome();
  Warnings(0);
  Estimate();
  Figure("std-vs-bound", 960, 300);
  Engineering();
  Verdict();
  UnitHistory();
  for (const RunView& run : in_.runs) Run(run);
  out_ += "<script type=\"application/json\" id=\"report-data\">" +
          ScriptSafeJson(data_.dump(-1, ' ', false, json::error_handler_t::replace)) +
          "</script>\n<script>\n" + chart_js + "\n</script>\n<script>" + kPageScript +
          "</script>\n</body>\n</html>\n";
  return std::move(out_);
}

int WarningRun(const std::string& warning) {
  if (warning.rfind("run ", 0) != 0) return 0;
  std::size_t i = 4;
  int id = 0;
  bool digits = false;
  while (i < warning.size() && std::isdigit(static_cast<unsigned char>(warning[i])) &&
         id < 100000) {
    id = id * 10 + (warning[i] - '0');
    digits = true;
    ++i;
  }
  if (!digits) return 0;
  if (i < warning.size() && warning[i] != ':' && warning[i] != ' ') return 0;
  return id;
}

std::string RenderHtml(const ReportInputs& inputs, const json& data, const std::string& chart_js) {
  Page page(inputs, data);
  return page.Render(chart_js);
}

}  // namespace hrgbench::report::internal
