#include "run_conditions.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "figure_spec.hpp"

namespace hrgbench::report::internal {
namespace {

using nlohmann::json;

// One condition of a run: its column (if the run CSV has it, one value per sample) and the
// values session.json holds at the run's start and end.
struct Condition {
  const char* column;  // run CSV header
  const char* key;     // derived.runs[id] prefix: "<key>_over_run", "<key>_min_<unit>", ...
  const char* unit;    // "c" or "hz": the suffix of the derived keys
  const char* label;   // what the legend and caption call it
  const std::vector<double>& values;
  double start = std::nan("");
  double end = std::nan("");

  bool Series(const RunView& run) const {
    return !values.empty() && values.size() == run.data.t_s.size();
  }
  bool Ends() const { return std::isfinite(start) || std::isfinite(end); }
};

void AddSummary(const Condition& c, json* quality) {
  const std::string key = c.key;
  if (c.values.empty()) {
    (*quality)[key + "_over_run"] = nullptr;
    return;
  }
  const auto [low, high] = std::minmax_element(c.values.begin(), c.values.end());
  (*quality)[key + "_over_run"] = c.column;
  (*quality)[key + "_min_" + c.unit] = *low;
  (*quality)[key + "_max_" + c.unit] = *high;
  (*quality)[key + "_samples"] = c.values.size();
}

std::string Caption(const Condition& c, const RunView& run) {
  return std::string(c.label) +
         (c.Series(run)
              ? std::string(" from the run's ") + c.column +
                    " column (the electronics' last status at every sample, min/max "
                    "per bucket)"
              : std::string(" recorded at the run's start and end only (dashed: ") +
                    "nothing is recorded in between; the run CSV has no " + c.column + " column)");
}

}  // namespace

void AddRunConditions(const RunView& run, json* quality) {
  AddSummary({"temp_c", "temperature", "c", "temperature", run.temperature_c}, quality);
  AddSummary({"freq_hz", "frequency", "hz", "resonant frequency", run.resonant_frequency_hz},
             quality);
}

void AddConditionsFigure(const RunView& run, const session::RunRecord& recorded,
                         const MinMaxDecimator& decimator, json* figures) {
  const std::string id = std::to_string(run.id);
  bench::RunEnd end;
  if (recorded.end) end = recorded.end->values;
  const Condition temperature{"temp_c",
                              "temperature",
                              "c",
                              "temperature",
                              run.temperature_c,
                              end.temperature_start_c,
                              end.temperature_end_c};
  const Condition frequency{"freq_hz",
                            "frequency",
                            "hz",
                            "resonant frequency",
                            run.resonant_frequency_hz,
                            end.frequency_start_hz,
                            end.frequency_end_hz};
  const bool any_series = temperature.Series(run) || frequency.Series(run);
  if (!any_series && !temperature.Ends() && !frequency.Ends()) return;
  const std::vector<double> ends_t{run.first_t_s, run.last_t_s};
  const std::string caption = "Run " + id + ": the conditions over the run — " +
                              Caption(temperature, run) + "; " + Caption(frequency, run) +
                              " (right axis)";
  json figure = LineFigure("conditions-run-" + id, caption, "t [s]", "temperature [°C]",
                           any_series ? decimator.Times() : std::vector<double>{});
  figure["y2_label"] = "resonant frequency [Hz]";
  for (const Condition* c : {&temperature, &frequency}) {
    json series;
    if (c->Series(run)) {
      series = Series(std::string(c->label) + " (" + c->column + ")",
                      decimator.Apply(c->values.data(), 1));
    } else if (c->Ends()) {
      series =
          XySeries(std::string(c->label) + " at start and end", ends_t, {c->start, c->end}, true);
    } else {
      continue;
    }
    if (c == &frequency) series["axis"] = "y2";
    figure["series"].push_back(std::move(series));
  }
  figures->push_back(std::move(figure));
}

}  // namespace hrgbench::report::internal
