#pragma once
// The page under construction: the helpers that turn a JSON pointer into a table cell (the
// contract's data-source / data-derived elements) and the sections, one method each. Split over
// html_page.cpp (header, outcome, parameters, engineering, verdict, assembly) and
// page_run_section.cpp (one run's section). Internal to src/report; not thread-safe (one page,
// one thread).

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "html_text.hpp"
#include "report_data.hpp"
#include "report_inputs.hpp"

namespace hrgbench::report::internal {

// Attribute text for a JSON pointer ('/' kept: a pointer holds no URL).
inline std::string Attr(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

inline constexpr const char* kMissing = "<span class=\"na\">not recorded</span>";
inline constexpr const char* kNone = "<span class=\"na\">\u2014</span>";

class Page {
  using json = nlohmann::json;

 public:
  Page(const ReportInputs& in, const json& data) : in_(in), doc_(in.document), data_(data) {}

  // A number of session.json: <span data-source data-value>, or "—" when null/absent.
  std::string Src(const std::string& pointer) const {
    const double v = NumberAt(doc_, pointer);
    if (!std::isfinite(v)) return kNone;
    return "<span class=\"num\" data-source=\"" + Attr(pointer) + "\" data-value=\"" +
           RoundTrip(v) + "\">" + HtmlEscape(Readable(v)) + "</span>";
  }
  // A number the report derived: a pointer into the report-data block.
  std::string Der(const std::string& pointer) const { return Num(true, pointer); }
  // A number of session.json (derived = false) or of the report-data block (true) with the text
  // `text` (empty: Readable); data-value is always the full-precision value.
  std::string Num(bool derived, const std::string& pointer, const std::string& text = {}) const {
    const double v = NumberAt(derived ? data_ : doc_, pointer);
    if (!std::isfinite(v)) return kNone;
    return "<span class=\"num\" " + std::string(derived ? "data-derived" : "data-source") + "=\"" +
           Attr(pointer) + "\" data-value=\"" + RoundTrip(v) + "\">" +
           HtmlEscape(text.empty() ? Readable(v) : text) + "</span>";
  }
  // A value and its std as two cells, written to the std's precision (Metrological).
  std::pair<std::string, std::string> WithStd(bool derived, const std::string& value_pointer,
                                              const std::string& std_pointer) const {
    const json& d = derived ? data_ : doc_;
    const ValueWithStd t = Metrological(NumberAt(d, value_pointer), NumberAt(d, std_pointer));
    return {Num(derived, value_pointer, t.value), Num(derived, std_pointer, t.std)};
  }
  std::string Text(const std::string& pointer) const {
    const json* v = At(doc_, pointer);
    if (v == nullptr || v->is_null()) return kMissing;
    if (v->is_string()) return HtmlEscape(v->get<std::string>());
    if (v->is_boolean()) return v->get<bool>() ? "yes" : "no";
    if (v->is_number()) return Src(pointer);
    return HtmlEscape(v->dump());
  }
  bool Has(const std::string& pointer) const {
    const json* v = At(doc_, pointer);
    return v != nullptr && !v->is_null();
  }
  std::size_t Size(const json& d, const std::string& pointer) const {
    const json* v = At(d, pointer);
    return v != nullptr && v->is_array() ? v->size() : 0;
  }

  std::string Render(const std::string& chart_js);

 private:
  void Head();
  void Meta();
  void Outcome();
  void Warnings(int run);
  void Estimate();
  void Engineering();
  void EngineeringBudgets(const std::string& base);
  void Verdict();
  void UnitHistory();
  void Figure(const std::string& name, int width, int height);
  void Run(const RunView& run);

  const ReportInputs& in_;
  const json& doc_;
  const json& data_;
  std::map<std::string, std::string> captions_;  // figure name → caption
  std::map<int, std::vector<std::string>> warnings_by_run_;
  std::string out_;
};

}  // namespace hrgbench::report::internal
