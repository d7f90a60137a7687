#include "html_page.hpp"

#include <cctype>
#include <map>
#include <string>
#include <vector>

#include "guard_band_bar.hpp"
#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/session/session_record_keys.hpp"
#include "html_text.hpp"
#include "page.hpp"
#include "page_pointer.hpp"
#include "page_script.hpp"
#include "report_data.hpp"
#include "trend_plot.hpp"

namespace hrgbench::report::internal {

using nlohmann::json;
namespace keys = session::keys;

void Page::Head() {
  out_ +=
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>HRG session "
      "report " +
      TextOrMissing(record_.unit_serial) +
      "</title>\n<style>\n"
      "body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1000px;color:#222}\n"
      "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 6px;"
      "text-align:left;vertical-align:top}th{background:#f2f2f2}\n"
      ".num{font-variant-numeric:tabular-nums}.na{color:#888}\n"
      "svg.trend{margin:0 .5em .5em 0}\n"
      "#outcome{font-size:1.6em;font-weight:bold;padding:.5em .8em;border-radius:6px;color:#fff;"
      "margin:.8em 0}\n"
      "#outcome[data-kind=PASS]{background:#1b7f3b}#outcome[data-kind=FAIL]{background:#b3261e}"
      "#outcome:not([data-kind=PASS]):not([data-kind=FAIL]){background:#b26a00}\n"
      "#outcome .reason{font-size:.6em;font-weight:normal;display:block}\n"
      "li.warning{color:#8a4b00}\nfigure{margin:1em 0;page-break-inside:avoid}"
      "canvas{max-width:100%}figcaption{font-size:.9em;color:#444}\n"
      "section.run{border-top:2px solid #888;margin-top:2em;page-break-before:always}\n"
      ".status-FAIL{color:#b3261e;font-weight:bold}.status-PASS{color:#1b7f3b}\n"
      "@page{size:" +
      std::string(in_.paper == PaperSize::kLetter ? "letter" : "A4") +
      ";margin:12mm}\n"
      "</style>\n</head>\n<body>\n";
}

void Page::Meta() {
  out_ += "<h1>HRG session report: unit " + TextOrMissing(record_.unit_serial) +
          "</h1>\n<table class=\"meta\">\n";
  const auto row = [&](const char* name, const std::string& value) {
    out_ += std::string("<tr><th>") + name + "</th><td>" + value + "</td></tr>\n";
  };
  row("unit serial", TextOrMissing(record_.unit_serial));
  row("operator", TextOrMissing(record_.operator_name));
  row("station", TextOrMissing(record_.station_name));
  if (!record_.fixture_position.empty())
    row("fixture position", HtmlEscape(record_.fixture_position));
  row("software version", TextOrMissing(record_.software_version));
  const session::ConfigHashesRecord& hashes = record_.config_sha256;
  if (hashes.recorded) {
    row("config sha256: station", TextOrMissing(hashes.station_sha256));
    row("config sha256: sequence", TextOrMissing(hashes.sequence_sha256));
    row("config sha256: limits", TextOrMissing(hashes.limits_sha256));
  } else if (!record_.spec_sha256.empty()) {
    row("spec sha256", HtmlEscape(record_.spec_sha256));
  } else {
    row("config hashes", kMissing);
  }
  row("started (UTC)", TextOrMissing(record_.started ? record_.started->utc : std::string()));
  row("ended (UTC)", TextOrMissing(record_.ended ? record_.ended->utc : std::string()));
  row("state", TextOrMissing(record_.state));
  if (!record_.description.empty()) row("description", HtmlEscape(record_.description));
  row("session directory", HtmlEscape(in_.session_dir.string()));
  out_ += "</table>\n";
  // What the operator was asked to do at the table and who confirmed it, when (the sequence's
  // [[prompts]]; an interrupted one says why).
  if (record_.prompts.empty()) return;
  out_ +=
      "<h2>Operator prompts</h2>\n<table id=\"prompts\"><tr><th>prompt</th><th>where</th>"
      "<th>what</th><th>answer</th><th>by</th><th>how</th><th>shown (UTC)</th>"
      "<th>answered (UTC)</th></tr>\n";
  for (const session::PromptRecord& p : record_.prompts) {
    const std::string answer = p.answer.empty()
                                   ? std::string("open")
                                   : p.answer + (p.reason.empty() ? "" : ": " + p.reason);
    out_ += "<tr><td>" + HtmlEscape(p.id) + "</td><td>" + HtmlEscape(p.at) + "</td><td>" +
            HtmlEscape(p.text) + "</td><td>" + HtmlEscape(answer) + "</td><td>" +
            (p.by.empty() ? std::string(p.how == "auto" ? "nobody" : "—") : HtmlEscape(p.by)) +
            "</td><td>" + TextOrMissing(p.how) + "</td><td>" +
            TextOrMissing(p.shown ? p.shown->utc : std::string()) + "</td><td>" +
            TextOrMissing(p.answered ? p.answered->utc : std::string()) + "</td></tr>\n";
  }
  out_ += "</table>\n";
}

void Page::Outcome() {
  if (!record_.outcome) {
    out_ +=
        "<div id=\"outcome\" data-kind=\"NOT RECORDED\">NOT RECORDED<span class=\"reason\">"
        "session.json has no outcome (a session from hrg-sim, an older format, or one that did "
        "not close); the estimate below is the report's own</span></div>\n";
    return;
  }
  const session::OutcomeRecord& outcome = *record_.outcome;
  const std::string k(bench::ToString(outcome.kind));
  out_ += "<div id=\"outcome\" data-kind=\"" + Attr(k) + "\">" + HtmlEscape(k) +
          "<span class=\"reason\">" + HtmlEscape(outcome.reason) + " (exit code " +
          Src(Pointer(keys::kOutcome, keys::kExitCode),
              outcome.exit_code ? *outcome.exit_code : session::kNotRecorded) +
          ")</span></div>\n";
  if (!outcome.failed_parameters.empty()) {
    out_ += "<p>Out of limits:</p><ul>";
    for (std::size_t i = 0; i < outcome.failed_parameters.size(); ++i) {
      const bench::FailedParameter& f = outcome.failed_parameters[i];
      const auto p = [&](const char* key) {
        return Pointer(keys::kOutcome, keys::kFailedParameters, i, key);
      };
      out_ += "<li>" + HtmlEscape(f.name) + " = " + Src(p(keys::kValue), f.value) + " (limits " +
              Src(p(keys::kMin), f.min) + " … " + Src(p(keys::kMax), f.max) + ")</li>";
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
  const session::EstimateRecord* of_record =
      record_.outcome && record_.outcome->estimate ? &*record_.outcome->estimate : nullptr;
  const bool recorded = of_record != nullptr && of_record->delta_recorded;
  // The recorded estimate (outcome.estimate) or the report's own (/derived/estimate in the
  // report-data block).
  const auto pointer = [&](const char* key, auto... index) {
    return recorded ? EstimatePointer(key, index...)
                    : Pointer("derived", keys::kEstimate, key, index...);
  };
  const auto value = [&](const char* key, double recorded_value) {
    return recorded ? Src(pointer(key), recorded_value) : Der(pointer(key));
  };
  out_ += "<h2>Model parameters δ and ξ</h2>\n<p>";
  out_ += recorded ? "As recorded by the bench (outcome.estimate, method " +
                         TextOrMissing(of_record->method) + ")."
                   : std::string("Not recorded in session.json: estimated by the report (ml).");
  out_ += " The Cramér–Rao bound is of the session's own design (derived by the report).</p>\n";
  // The simulated truth: the estimate's copy, else the simulator's section.
  const std::array<double, 6>* truth_delta = nullptr;
  const std::array<double, 4>* truth_xi = nullptr;
  std::array<double, 4> no_xi;
  no_xi.fill(session::kNotRecorded);
  std::string truth_pointer;  // "" when there is no truth
  if (of_record != nullptr && of_record->truth_delta) {
    truth_delta = &*of_record->truth_delta;
    truth_xi = of_record->truth_xi ? &*of_record->truth_xi : &no_xi;
    truth_pointer = EstimatePointer(keys::kTruth);
  } else if (record_.simulation_delta) {
    truth_delta = &*record_.simulation_delta;
    truth_xi = record_.simulation_xi ? &*record_.simulation_xi : &no_xi;
    truth_pointer = Pointer(keys::kSimulation);
  }
  out_ +=
      "<table class=\"parameters\"><tr><th>parameter</th><th>meaning</th><th>estimate</th>"
      "<th>± std</th>";
  if (truth_delta != nullptr) out_ += "<th>truth (simulated)</th><th>(estimate − truth)/std</th>";
  out_ += "<th>Cramér–Rao std</th></tr>\n";
  for (std::size_t p = 0; p < 10; ++p) {
    const bool is_delta = p < 6;
    const std::size_t i = is_delta ? p : p - 6;
    const char* key = is_delta ? keys::kDelta : keys::kXi;
    const char* std_key = is_delta ? keys::kDeltaStd : keys::kXiStd;
    double recorded_value = session::kNotRecorded, recorded_std = session::kNotRecorded;
    if (recorded) {
      recorded_value = is_delta ? of_record->delta[i] : of_record->xi[i];
      recorded_std = is_delta ? of_record->delta_std[i] : of_record->xi_std[i];
    }
    const auto [estimate, std_dev] =
        recorded ? SrcWithStd(pointer(key, i), recorded_value, pointer(std_key, i), recorded_std)
                 : DerWithStd(pointer(key, i), pointer(std_key, i));
    out_ += "<tr><td>" + std::string(is_delta ? "δ" : "ξ") + std::to_string(i + 1) + "</td><td>" +
            std::string(is_delta ? estimator::kDeltaMeanings[i] : estimator::kXiMeanings[i]) +
            "</td><td>" + estimate + "</td><td>" + std_dev + "</td>";
    const double std_value = recorded ? recorded_std : NumberAt(data_, pointer(std_key, i));
    if (truth_delta != nullptr) {
      // The truth to the estimate's precision, so the two columns read side by side.
      const double truth = is_delta ? (*truth_delta)[i] : (*truth_xi)[i];
      const std::string z = Pointer("derived", "truth_deviation", key, i);
      out_ += "<td>" +
              Src(truth_pointer + Pointer(key, i), truth, Metrological(truth, std_value).value) +
              "</td><td>" + Der(z, Fixed(NumberAt(data_, z), 2)) + "</td>";
    }
    const std::string bound = Pointer("derived", "crlb", std_key, i);
    out_ += "<td>" + Der(bound, TwoSignificant(NumberAt(data_, bound))) + "</td></tr>\n";
  }
  const auto count = [](auto n) { return static_cast<double>(n); };
  out_ += "</table>\n<p>Residual RMS " +
          value(keys::kResidualRms, recorded ? of_record->residual_rms : 0.0) + ", noise σ̂ " +
          value(keys::kNoiseSigma, recorded ? of_record->noise_sigma : 0.0) + ", " +
          value(keys::kSamplesUsed, recorded ? count(of_record->samples_used) : 0.0) +
          " samples, " + value(keys::kIterations, recorded ? count(of_record->iterations) : 0.0) +
          " iterations.</p>\n";
}

// One table of every quantity's uncertainty budget (GUM: components with their sources, the
// combined standard uncertainty and the coverage factor), largest component first as recorded.
void Page::EngineeringBudgets(const session::EstimateRecord& estimate) {
  const auto pointer = [](auto... parts) { return EstimatePointer(keys::kEngineering, parts...); };
  std::string rows;
  for (std::size_t i = 0; i < estimate.engineering.size(); ++i) {
    const session::EngineeringQuantityRecord& q = estimate.engineering[i];
    if (q.budget.empty()) continue;
    const std::string unit = HtmlEscape(q.unit);
    rows += "<tr class=\"budget-total\"><td rowspan=\"" + std::to_string(q.budget.size() + 1) +
            "\">" + (q.label.empty() ? TextOrMissing(q.name) : HtmlEscape(q.label)) +
            "</td><td>combined u<sub>c</sub></td><td></td><td>" +
            Src(pointer(keys::kQuantities, i, keys::kStd), q.std) + " " + unit +
            "</td><td></td></tr>\n";
    for (std::size_t c = 0; c < q.budget.size(); ++c) {
      const session::UncertaintyComponentRecord& b = q.budget[c];
      const bool evaluated = !std::isnan(b.standard_uncertainty);
      rows +=
          "<tr><td>" + HtmlEscape(b.source) + "</td><td>" + HtmlEscape(b.type) + "</td><td>" +
          (evaluated
               ? Src(pointer(keys::kQuantities, i, keys::kBudget, c, keys::kStandardUncertainty),
                     b.standard_uncertainty) +
                     " " + unit
               : std::string("<span class=\"na\">not evaluated</span>")) +
          "</td><td>" + HtmlEscape(b.note) + "</td></tr>\n";
    }
  }
  if (rows.empty()) return;
  out_ +=
      "<h3>Uncertainty budgets</h3>\n<p>Each quantity's components (type A: from this "
      "session's data; type B: from a model or a declaration), largest first. The verdict "
      "judges u<sub>c</sub>; the expanded uncertainty is U = " +
      Src(pointer(keys::kCoverageFactor), estimate.engineering_coverage_factor) +
      "·u<sub>c</sub>.</p>\n<table class=\"budget\"><tr><th>quantity</th><th>component</th>"
      "<th>type</th><th>standard uncertainty</th><th>how</th></tr>\n" +
      rows + "</table>\n";
  for (const std::string& limitation : estimate.engineering_limitations)
    out_ += "<p class=\"note\">" + HtmlEscape(limitation) + "</p>\n";
}

void Page::Engineering() {
  out_ += "<h2>The resonator in its own units</h2>\n";
  const session::EstimateRecord* estimate =
      record_.outcome && record_.outcome->estimate ? &*record_.outcome->estimate : nullptr;
  const bool recorded = estimate != nullptr && estimate->engineering_recorded;
  if (!recorded) {
    out_ += "<p>Engineering quantities: " + std::string(kMissing) +
            " (session.json has no outcome.estimate.engineering).</p>\n";
  } else {
    const auto pointer = [](auto... parts) {
      return EstimatePointer(keys::kEngineering, parts...);
    };
    out_ += "<p>Carrier frequency " +
            Src(pointer(keys::kFrequencyHz), estimate->engineering_frequency_hz) + " Hz (" +
            TextOrMissing(estimate->engineering_frequency_source) +
            ").</p>\n<table class=\"engineering\"><tr><th>"
            "quantity</th><th>value</th><th>± u<sub>c</sub></th><th>unit</th><th>note</th></tr>\n";
    for (std::size_t i = 0; i < estimate->engineering.size(); ++i) {
      const session::EngineeringQuantityRecord& q = estimate->engineering[i];
      out_ +=
          "<tr><td>" + (q.label.empty() ? TextOrMissing(q.name) : HtmlEscape(q.label)) + "</td>";
      if (q.determined) {
        const auto [value, std_dev] =
            SrcWithStd(pointer(keys::kQuantities, i, keys::kValue), q.value,
                       pointer(keys::kQuantities, i, keys::kStd), q.std);
        out_ += "<td>" + value + "</td><td>" + std_dev + "</td>";
      } else {
        out_ += "<td colspan=\"2\" class=\"na\">undetermined</td>";
      }
      out_ += "<td>" + HtmlEscape(q.unit) + "</td><td>" + HtmlEscape(q.note) + "</td></tr>\n";
    }
    out_ += "</table>\n";
    EngineeringBudgets(*estimate);
  }
  // The report's own anisotropy only when the record has none (the table above is the record's,
  // and says which axes are determined).
  const json* a = At(data_, "/derived/anisotropy");
  if (!recorded && a != nullptr && a->is_object()) {
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
  if (!record_.outcome || !record_.outcome->verdict) {
    out_ += "<p>Verdict: " + std::string(kMissing) +
            " (session.json has no outcome.verdict).</p>\n<h2>Fit checks</h2>\n<p>" + kMissing +
            "</p>\n";
    return;
  }
  const session::VerdictRecord& verdict = *record_.outcome->verdict;
  const auto pointer = [](auto... parts) {
    return Pointer(keys::kOutcome, keys::kVerdict, parts...);
  };
  out_ += "<p>Overall " + TextOrMissing(verdict.overall) +
          "; the fit within its model: " + YesNo(verdict.fit_acceptable) + ".</p>\n";
  out_ +=
      "<table class=\"limits\"><tr><th>quantity</th><th>value</th><th>± std</th><th>min</th>"
      "<th>max</th><th>status</th><th>value ± k·u against the limits</th><th>message</th>"
      "</tr>\n";
  for (std::size_t i = 0; i < verdict.limits.size(); ++i) {
    const session::LimitRowRecord& l = verdict.limits[i];
    const auto at = [&](const char* key) { return pointer(keys::kLimits, i, key); };
    // The value to the digits its std supports (GUM 7.2.6), as in the parameter table.
    const auto [value, std_dev] = SrcWithStd(at(keys::kValue), l.value, at(keys::kStd), l.std);
    out_ += "<tr><td>" + HtmlEscape(l.quantity) + "</td><td>" + value + "</td><td>" + std_dev +
            "</td><td>" + Src(at(keys::kMin), l.min) + "</td><td>" + Src(at(keys::kMax), l.max) +
            "</td><td class=\"status-" + Attr(l.status) + "\">" + HtmlEscape(l.status) +
            "</td><td>" + GuardBandBar(l) + "</td><td>" + HtmlEscape(l.message) + "</td></tr>\n";
  }
  out_ += "</table>\n";
  if (!verdict.decision_rule.empty())
    out_ += "<p class=\"decision\">Decision rule " + HtmlEscape(verdict.decision_rule) +
            ", k = " + Readable(verdict.decision_coverage_factor) +
            " (the bar: the tolerance, its guard bands shaded, the value with v ± k·u; "
            "docs/reference/config-keys.md)" +
            (verdict.retest.value_or(false) ? "; undecided within the guard band: retest" : "") +
            ".</p>\n";
  out_ += "<h2>Fit checks</h2>\n";
  out_ +=
      "<table class=\"fit-checks\"><tr><th>run</th><th>check</th><th>value</th><th>max</th>"
      "<th>status</th><th>message</th></tr>\n";
  for (std::size_t i = 0; i < verdict.fit_checks.size(); ++i) {
    const session::FitCheckRecord& c = verdict.fit_checks[i];
    const auto at = [&](const char* key) { return pointer(keys::kFitChecks, i, key); };
    out_ += "<tr><td>" + Src(at(keys::kRun), c.run) + "</td><td>" + HtmlEscape(c.name) +
            "</td><td>" + Src(at(keys::kValue), c.value) + "</td><td>" +
            Src(at(keys::kMax), c.max) + "</td><td class=\"status-" + Attr(c.status) + "\">" +
            HtmlEscape(c.status) + "</td><td>" + HtmlEscape(c.message) + "</td></tr>\n";
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
  const std::size_t shown = DerivedSize("/derived/unit_history/sessions");
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
  const std::string kind =
      record_.outcome ? std::string(bench::ToString(record_.outcome->kind)) : std::string();
  out_ += "<tr class=\"this-session\"><td>" +
          TextOrMissing(record_.started ? record_.started->utc : std::string()) + "</td><td>" +
          TextOrMissing(record_.station_name) + "</td><td class=\"status-" + Attr(kind) + "\">" +
          HtmlEscape(kind) + " (this session)</td>";
  const session::EstimateRecord* estimate =
      record_.outcome && record_.outcome->estimate ? &*record_.outcome->estimate : nullptr;
  for (const auto& [name, label] : kHistoryColumns) {
    std::string cell = kNone;
    for (std::size_t q = 0; estimate != nullptr && q < estimate->engineering.size(); ++q) {
      const session::EngineeringQuantityRecord& quantity = estimate->engineering[q];
      if (quantity.name == name)
        cell = Src(EstimatePointer(keys::kEngineering, keys::kQuantities, q, keys::kValue),
                   quantity.value);
    }
    out_ += "<td>" + cell + "</td>";
  }
  out_ += "</tr>\n</table>\n";
  UnitTrends(shown);
  out_ += "</section>\n";
}

// One small plot per key quantity: the earlier sessions' values ± k·u (the data block's copy of
// the store's rows) and this session's from its record, against this session's limits.
void Page::UnitTrends(std::size_t shown) {
  const session::EstimateRecord* estimate =
      record_.outcome && record_.outcome->estimate ? &*record_.outcome->estimate : nullptr;
  const session::VerdictRecord* verdict =
      record_.outcome && record_.outcome->verdict ? &*record_.outcome->verdict : nullptr;
  // The k the verdict judged with, else the engineering quantities' own, else 1 (bars of u).
  double k = verdict != nullptr ? verdict->decision_coverage_factor : session::kNotRecorded;
  if (!(std::isfinite(k) && k > 0.0) && estimate != nullptr)
    k = estimate->engineering_coverage_factor;
  if (!(std::isfinite(k) && k > 0.0)) k = 1.0;
  std::string plots;
  for (const auto& [name, label] : kHistoryColumns) {
    std::vector<TrendPoint> points;
    for (std::size_t i = 0; i < shown; ++i) {
      const std::string s = "/derived/unit_history/sessions/" + std::to_string(i);
      const json* started = At(data_, s + "/started_utc");
      points.push_back(
          {started != nullptr && started->is_string() ? started->get<std::string>() : std::string(),
           NumberAt(data_, s + "/values/" + name), NumberAt(data_, s + "/stds/" + name), false});
    }
    TrendPoint current{"this session", session::kNotRecorded, session::kNotRecorded, true};
    for (std::size_t q = 0; estimate != nullptr && q < estimate->engineering.size(); ++q) {
      if (estimate->engineering[q].name != name) continue;
      current.value = estimate->engineering[q].value;
      current.std_dev = estimate->engineering[q].std;
    }
    points.push_back(current);
    std::optional<double> low, high;
    for (std::size_t i = 0; verdict != nullptr && i < verdict->limits.size(); ++i) {
      const session::LimitRowRecord& l = verdict->limits[i];
      if (l.quantity != name) continue;
      if (std::isfinite(l.min)) low = l.min;
      if (std::isfinite(l.max)) high = l.max;
    }
    plots += TrendPlot(name, label, points, k, low, high);
  }
  if (plots.empty()) return;
  out_ +=
      "<div class=\"trends\"><p>The trend of each: one point per session (this one filled, "
      "last), bars ± " +
      Readable(k) + "·u where the store keeps u, this session's limits dashed.</p>\n" + plots +
      "</div>\n";
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
  Tuning();
  UnitHistory();
  RunList();
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
