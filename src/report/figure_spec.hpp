#pragma once
// The figure specs of the page's data block (report_data.hpp: figures [{name, caption, type,
// x_label, y_label, y_log, x_log?, equal_aspect, x, series [{label, y, x?, model, axis?,
// points?}]}]), built the same way by every part of the report that adds a figure. Internal to
// src/report.

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "html_text.hpp"

namespace hrgbench::report::internal {

// Numbers for a chart, rounded to 6 digits (the page need not carry 17); null where not finite.
inline nlohmann::json Numbers(const std::vector<double>& values) {
  nlohmann::json out = nlohmann::json::array();
  out.get_ref<nlohmann::json::array_t&>().reserve(values.size());
  for (const double v : values)
    out.push_back(std::isfinite(v) ? nlohmann::json(Rounded(v)) : nlohmann::json(nullptr));
  return out;
}

// A series on the figure's common abscissa; `model` draws it dashed.
inline nlohmann::json Series(const std::string& label, const std::vector<double>& y,
                             bool model = false) {
  return nlohmann::json{{"label", label}, {"y", Numbers(y)}, {"model", model}};
}

// A series with its own abscissa.
inline nlohmann::json XySeries(const std::string& label, const std::vector<double>& x,
                               const std::vector<double>& y, bool model = false) {
  nlohmann::json s = Series(label, y, model);
  s["x"] = Numbers(x);
  return s;
}

// A series on the figure's right-hand axis (y2_label).
inline nlohmann::json RightSeries(const std::string& label, const std::vector<double>& y,
                                  bool model = false) {
  nlohmann::json s = Series(label, y, model);
  s["axis"] = "y2";
  return s;
}

inline nlohmann::json LineFigure(const std::string& name, const std::string& caption,
                                 const std::string& x_label, const std::string& y_label,
                                 const std::vector<double>& x) {
  return nlohmann::json{
      {"name", name},          {"caption", caption}, {"type", "line"},
      {"x_label", x_label},    {"y_label", y_label}, {"y_log", false},
      {"equal_aspect", false}, {"x", Numbers(x)},    {"series", nlohmann::json::array()}};
}

}  // namespace hrgbench::report::internal
