#pragma once
// The page under construction: the helpers that turn a value of the typed record (with its JSON
// pointer, page_pointer.hpp) or of the report-data block into a table cell (the contract's
// data-source / data-derived elements) and the sections, one method each. Split over
// html_page.cpp (header, outcome, parameters, engineering, verdict, assembly) and
// page_run_section.cpp (one run's section). Internal to src/report; not thread-safe (one page,
// one thread).

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hrgbench/session/session_record.hpp"
#include "html_text.hpp"
#include "page_pointer.hpp"
#include "report_data.hpp"
#include "report_inputs.hpp"

namespace hrgbench::report::internal {

// Attribute text for a JSON pointer. Not HtmlEscape: that writes '/' as &#47; so that nothing in
// the page reads as a URL; a pointer holds no URL, and its '/' are kept so the page's readers and
// tests match data-source="/outcome/..." as written.
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
  Page(const ReportInputs& in, const json& data) : in_(in), record_(in.record), data_(data) {}

  // A number of session.json, taken from the typed record (`value`), with its pointer into
  // session.json as data-source (page_pointer.hpp builds it from the key names): <span
  // data-source data-value>, or "—" when not finite (null or absent). `text` empty: Readable.
  std::string Src(const std::string& pointer, double value, const std::string& text = {}) const {
    return Number("data-source", pointer, value, text);
  }
  // A number of tune.json (the tuning's record, tune_data.hpp): its pointer into tune.json as
  // data-tune-source, its value read there.
  std::string TuneSrc(const std::string& pointer, const std::string& text = {}) const {
    return in_.tune ? Number("data-tune-source", pointer, NumberAt(*in_.tune, pointer), text)
                    : std::string(kNone);
  }
  // A number the report derived: a pointer into the report-data block (its value is read there).
  std::string Der(const std::string& pointer, const std::string& text = {}) const {
    return Number("data-derived", pointer, NumberAt(data_, pointer), text);
  }
  // A value and its std of session.json as two cells, written to the std's precision
  // (Metrological).
  std::pair<std::string, std::string> SrcWithStd(const std::string& value_pointer, double value,
                                                 const std::string& std_pointer,
                                                 double std_dev) const {
    const ValueWithStd t = Metrological(value, std_dev);
    return {Src(value_pointer, value, t.value), Src(std_pointer, std_dev, t.std)};
  }
  // The same for two numbers of the report-data block.
  std::pair<std::string, std::string> DerWithStd(const std::string& value_pointer,
                                                 const std::string& std_pointer) const {
    const ValueWithStd t =
        Metrological(NumberAt(data_, value_pointer), NumberAt(data_, std_pointer));
    return {Der(value_pointer, t.value), Der(std_pointer, t.std)};
  }
  // A recorded text; "not recorded" when empty (the reader's absent or null).
  static std::string TextOrMissing(const std::string& text) {
    return text.empty() ? std::string(kMissing) : HtmlEscape(text);
  }
  // The length of an array of the report-data block (0 when not an array).
  std::size_t DerivedSize(const std::string& pointer) const {
    const json* v = At(data_, pointer);
    return v != nullptr && v->is_array() ? v->size() : 0;
  }
  static std::string YesNo(const std::optional<bool>& value) {
    if (!value) return kMissing;
    return *value ? "yes" : "no";
  }

  std::string Render(const std::string& chart_js);

 private:
  void Head();
  void Meta();
  void Outcome();
  void Warnings(int run);
  void Estimate();
  void Engineering();
  void EngineeringBudgets(const session::EstimateRecord& estimate);
  void Verdict();
  void UnitHistory();
  void Tuning();                       // page_tune_section.cpp
  void UnitTrends(std::size_t shown);  // the trend plots under the history table
  void Figure(const std::string& name, int width, int height);
  void Run(const RunView& run);
  // When not every run has figures: one row per run (figures drawn or not) above the sections.
  void RunList();
  std::string Number(const char* attribute, const std::string& pointer, double value,
                     const std::string& text) const {
    if (!std::isfinite(value)) return kNone;
    return "<span class=\"num\" " + std::string(attribute) + "=\"" + Attr(pointer) +
           "\" data-value=\"" + RoundTrip(value) + "\">" +
           HtmlEscape(text.empty() ? Readable(value) : text) + "</span>";
  }

  const ReportInputs& in_;
  const session::SessionRecord& record_;  // session.json as its one reader typed it
  const json& data_;
  std::map<std::string, std::string> captions_;  // figure name → caption
  std::map<int, std::vector<std::string>> warnings_by_run_;
  std::string out_;
};

}  // namespace hrgbench::report::internal
