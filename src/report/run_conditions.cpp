#include "run_conditions.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "figure_spec.hpp"

namespace hrgbench::report::internal {

using nlohmann::json;

void AddRunConditions(const RunView& run, json* quality) {
  (*quality)["frequency_over_run"] = nullptr;
  const std::vector<double>& t = run.temperature_c;
  if (t.empty()) {
    (*quality)["temperature_over_run"] = nullptr;
    return;
  }
  const auto [low, high] = std::minmax_element(t.begin(), t.end());
  (*quality)["temperature_over_run"] = "temp_c";
  (*quality)["temperature_min_c"] = *low;
  (*quality)["temperature_max_c"] = *high;
  (*quality)["temperature_samples"] = t.size();
}

void AddConditionsFigure(const RunView& run, const session::RunRecord& recorded,
                         const MinMaxDecimator& decimator, json* figures) {
  const std::string id = std::to_string(run.id);
  bench::RunEnd end;
  if (recorded.end) end = recorded.end->values;
  const bool series = !run.temperature_c.empty() && run.temperature_c.size() == run.data.t_s.size();
  const bool temperature_ends =
      std::isfinite(end.temperature_start_c) || std::isfinite(end.temperature_end_c);
  const bool frequency_ends =
      std::isfinite(end.frequency_start_hz) || std::isfinite(end.frequency_end_hz);
  if (!series && !temperature_ends && !frequency_ends) return;
  const std::vector<double> ends_t{run.first_t_s, run.last_t_s};
  std::string caption = "Run " + id + ": the conditions over the run — temperature ";
  caption += series ? "from the run's temp_c column (every sample, min/max per bucket)"
                    : "recorded at the run's start and end only (dashed: nothing is recorded in "
                      "between; the run CSV has no temp_c column)";
  caption +=
      "; resonant frequency (right axis) recorded at the run's start and end only (dashed: "
      "session.json keeps no series of it)";
  json figure = LineFigure("conditions-run-" + id, caption, "t [s]", "temperature [°C]",
                           series ? decimator.Times() : std::vector<double>{});
  figure["y2_label"] = "resonant frequency [Hz]";
  if (series) {
    figure["series"].push_back(
        Series("temperature (temp_c)", decimator.Apply(run.temperature_c.data(), 1)));
  } else if (temperature_ends) {
    figure["series"].push_back(XySeries("temperature at start and end", ends_t,
                                        {end.temperature_start_c, end.temperature_end_c}, true));
  }
  if (frequency_ends) {
    json f = XySeries("resonant frequency at start and end", ends_t,
                      {end.frequency_start_hz, end.frequency_end_hz}, true);
    f["axis"] = "y2";
    figure["series"].push_back(std::move(f));
  }
  figures->push_back(std::move(figure));
}

}  // namespace hrgbench::report::internal
