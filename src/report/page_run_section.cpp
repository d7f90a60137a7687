// One run's section of the page: its warnings, capture quality, recorded fit and four figures.
#include <cmath>
#include <string>

#include "hrgbench/session/session_record_keys.hpp"
#include "page.hpp"
#include "page_pointer.hpp"

namespace hrgbench::report::internal {

namespace keys = session::keys;
using nlohmann::json;

void Page::Run(const RunView& run) {
  const std::string id = std::to_string(run.id);
  // RunView::index is the run's position in session.json "runs", as in the record's list.
  const session::RunRecord& recorded = record_.runs.at(run.index);
  out_ += "<section class=\"run\" id=\"run-" + id + "\" data-run=\"" + id + "\">\n<h2>Run " + id +
          ": Ω " + Src(RunPointer(run.index, keys::kOmegaRadS), recorded.omega_rad_s) +
          " rad/s, status " + TextOrMissing(recorded.status) + "</h2>\n";
  Warnings(run.id);
  if (!run.loaded) out_ += "<p>Not drawn: " + HtmlEscape(run.not_loaded_reason) + ".</p>\n";
  out_ +=
      "<h3>Capture quality</h3>\n<table class=\"capture\"><tr><th>quantity</th><th>value</th>"
      "</tr>\n";
  const auto row = [&](const char* name, const std::string& value) {
    out_ += std::string("<tr><td>") + name + "</td><td>" + value + "</td></tr>\n";
  };
  const std::string d = "/derived/runs/" + id + "/";
  if (!recorded.end) row("end of run", kMissing);
  // What the recorder wrote of the run's end: the counts with the sample count (an end written
  // by a recorder error has neither), a number only when measured (null is not shown).
  if (recorded.end) {
    const session::RunEndRecord& end = *recorded.end;
    const bench::RunEnd& v = end.values;
    const auto count = [&](const char* name, const char* key, double value) {
      if (end.samples) row(name, Src(RunPointer(run.index, keys::kEnd, key), value));
    };
    const auto number = [&](const char* name, const char* key, double value) {
      if (std::isfinite(value)) row(name, Src(RunPointer(run.index, keys::kEnd, key), value));
    };
    count("samples recorded", keys::kSamples, static_cast<double>(end.samples.value_or(0)));
    count("sequence gaps", keys::kSequenceGaps, static_cast<double>(v.sequence_gaps));
    count("kernel drops", keys::kKernelDrops, static_cast<double>(v.kernel_drops));
    count("bad frames", keys::kBadFrames, static_cast<double>(v.bad_frames));
    number("Ω [rad/s]", keys::kOmegaRadS, v.omega_rad_s);
    number("Ω standard error [rad/s]", keys::kOmegaStdErrorRadS, v.omega_std_error_rad_s);
    number("table rate std error [rad/s]", keys::kOmegaRateStdErrorRadS,
           v.omega_rate_std_error_rad_s);
    number("temperature at start [°C]", keys::kTemperatureStartC, v.temperature_start_c);
    number("temperature at end [°C]", keys::kTemperatureEndC, v.temperature_end_c);
    number("frequency at start [Hz]", keys::kFrequencyStartHz, v.frequency_start_hz);
    number("frequency at end [Hz]", keys::kFrequencyEndHz, v.frequency_end_hz);
  }
  if (recorded.start && std::isfinite(recorded.start->values.resonant_frequency_hz)) {
    row("resonant frequency at release [Hz]",
        Src(RunPointer(run.index, keys::kStart, keys::kResonantFrequencyHz),
            recorded.start->values.resonant_frequency_hz));
  }
  if (run.loaded) {
    row("samples loaded", Der(d + "samples_loaded"));
    row("mean sample interval [s]", Der(d + "sample_interval_s"));
    row("sample-time jitter, std [s]", Der(d + "sample_time_jitter_std_s"));
    row("sample-time jitter, max |Δt − nominal| [s]", Der(d + "sample_time_jitter_max_s"));
    row("time gaps (Δt > 1.5 nominal)", Der(d + "time_gaps"));
    if (std::isfinite(NumberAt(data_, d + "temperature_drift_c")))
      row("temperature drift [°C]", Der(d + "temperature_drift_c"));
    if (std::isfinite(NumberAt(data_, d + "frequency_drift_hz")))
      row("frequency drift [Hz]", Der(d + "frequency_drift_hz"));
    // Over the run, not only at its ends; what was not recorded over it is said.
    struct Over {
      const char* key;
      const char* unit;
      const char* label;
      const char* column;
    };
    for (const Over& c :
         {Over{"temperature", "c", "temperature over the run [°C]", "temp_c"},
          Over{"frequency", "hz", "resonant frequency over the run [Hz]", "freq_hz"}}) {
      const std::string key = c.key;
      const json* over = At(data_, d + key + "_over_run");
      if (over != nullptr && over->is_string()) {
        row(c.label, Der(d + key + "_min_" + c.unit) + " … " + Der(d + key + "_max_" + c.unit) +
                         " (" + Der(d + key + "_samples") + " samples, " + c.column + ")");
      } else {
        row(c.label, std::string(kMissing) + " (the run CSV has no " + c.column +
                         " column: at start and end only)");
      }
    }
  }
  out_ += "</table>\n";
  // The fit of this run as recorded (outcome.estimate.fit.runs[k] with run == id).
  const session::EstimateRecord* estimate =
      record_.outcome && record_.outcome->estimate ? &*record_.outcome->estimate : nullptr;
  for (std::size_t k = 0; estimate != nullptr && k < estimate->fit_runs.size(); ++k) {
    const session::FitRunRecord& fit = estimate->fit_runs[k];
    if (fit.run != run.id) continue;
    const auto src = [&](const char* key, double value) {
      return Src(EstimatePointer(keys::kFit, keys::kRuns, k, key), value);
    };
    out_ +=
        "<h3>Fit</h3>\n<table class=\"fit\"><tr><th>residual RMS</th><th>noise σ</th><th>"
        "ratio</th><th>whiteness z</th><th>outliers removed</th><th>Ω offset [std]</th></tr>"
        "<tr><td>" +
        src(keys::kResidualRms, fit.residual_rms) + "</td><td>" +
        src(keys::kNoiseSigma, fit.noise_sigma) + "</td><td>" +
        src(keys::kResidualRatio, fit.residual_ratio) + "</td><td>" +
        src(keys::kWhitenessZ, fit.whiteness_z) + "</td><td>" +
        src(keys::kOutliersRemoved, fit.outliers_removed) + "</td><td>" +
        src(keys::kOmegaOffsetInStd, fit.omega_offset_in_std) + "</td></tr></table>\n";
  }
  if (run.loaded && run.figures) {
    for (const char* kind : {"channels", "motion", "residuals", "residual-histogram",
                             "residual-spectrum", "orbit", "forms", "conditions"})
      Figure(std::string(kind) + "-run-" + id, 960, 300);
  } else if (run.loaded) {
    out_ +=
        "<p class=\"na\">Figures not drawn: the page draws the figures of a bounded number of runs "
        "(the first, the last and those with the largest residual RMS; see the run list).</p>\n";
  }
  out_ += "</section>\n";
}

void Page::RunList() {
  std::size_t without = 0;
  for (const RunView& run : in_.runs) without += run.loaded && !run.figures ? 1 : 0;
  if (without == 0) return;
  const session::EstimateRecord* estimate =
      record_.outcome && record_.outcome->estimate ? &*record_.outcome->estimate : nullptr;
  out_ += "<section id=\"run-list\"><h2>Runs</h2>\n<p>" + std::to_string(in_.runs.size()) +
          " runs; figures are drawn for " + std::to_string(in_.runs.size() - without) +
          " of them (the first, the last and the largest residual RMS), so that the page's size "
          "does not grow with the number of runs beyond a few kB per run.</p>\n"
          "<table class=\"runs\"><tr><th>run</th><th>Ω [rad/s]</th><th>status</th><th>samples "
          "loaded</th><th>residual RMS</th><th>figures</th></tr>\n";
  for (const RunView& run : in_.runs) {
    const std::string id = std::to_string(run.id);
    const session::RunRecord& recorded = record_.runs.at(run.index);
    std::string rms = kNone;
    for (std::size_t k = 0; estimate != nullptr && k < estimate->fit_runs.size(); ++k)
      if (estimate->fit_runs[k].run == run.id)
        rms = Src(EstimatePointer(keys::kFit, keys::kRuns, k, keys::kResidualRms),
                  estimate->fit_runs[k].residual_rms);
    out_ += "<tr><td><a href=\"#run-" + id + "\">" + id + "</a></td><td>" +
            Src(RunPointer(run.index, keys::kOmegaRadS), recorded.omega_rad_s) + "</td><td>" +
            TextOrMissing(recorded.status) + "</td><td>" +
            (run.loaded ? Der("/derived/runs/" + id + "/samples_loaded") : std::string(kNone)) +
            "</td><td>" + rms + "</td><td>" + (run.figures && run.loaded ? "yes" : "no") +
            "</td></tr>\n";
  }
  out_ += "</table></section>\n";
}

}  // namespace hrgbench::report::internal
