// One run's section of the page: its warnings, capture quality, recorded fit and four figures.
#include <cmath>
#include <string>

#include "page.hpp"

namespace hrgbench::report::internal {

void Page::Run(const RunView& run) {
  const std::string id = std::to_string(run.id);
  const std::string r = "/runs/" + std::to_string(run.index);
  out_ += "<section class=\"run\" id=\"run-" + id + "\" data-run=\"" + id + "\">\n<h2>Run " + id +
          ": Ω " + Src(r + "/omega_rad_s") + " rad/s, status " + Text(r + "/status") + "</h2>\n";
  Warnings(run.id);
  if (!run.loaded) out_ += "<p>Not drawn: " + HtmlEscape(run.not_loaded_reason) + ".</p>\n";
  out_ +=
      "<h3>Capture quality</h3>\n<table class=\"capture\"><tr><th>quantity</th><th>value</th>"
      "</tr>\n";
  const auto row = [&](const char* name, const std::string& value) {
    out_ += std::string("<tr><td>") + name + "</td><td>" + value + "</td></tr>\n";
  };
  const std::string d = "/derived/runs/" + id + "/";
  if (!Has(r + "/end")) row("end of run", kMissing);
  const std::pair<const char*, const char*> recorded[] = {
      {"samples recorded", "/end/samples"},
      {"sequence gaps", "/end/sequence_gaps"},
      {"kernel drops", "/end/kernel_drops"},
      {"bad frames", "/end/bad_frames"},
      {"Ω [rad/s]", "/end/omega_rad_s"},
      {"Ω standard error [rad/s]", "/end/omega_std_error_rad_s"},
      {"table rate std error [rad/s]", "/end/omega_rate_std_error_rad_s"},
      {"temperature at start [°C]", "/end/temperature_start_c"},
      {"temperature at end [°C]", "/end/temperature_end_c"},
      {"frequency at start [Hz]", "/end/frequency_start_hz"},
      {"frequency at end [Hz]", "/end/frequency_end_hz"},
      {"resonant frequency at release [Hz]", "/start/resonant_frequency_hz"}};
  for (const auto& [name, key] : recorded)
    if (Has(r + key)) row(name, Src(r + key));
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
  }
  out_ += "</table>\n";
  // The fit of this run as recorded (outcome.estimate.fit.runs[k] with run == id).
  const std::size_t fits = Size(doc_, "/outcome/estimate/fit/runs");
  for (std::size_t k = 0; k < fits; ++k) {
    const std::string f = "/outcome/estimate/fit/runs/" + std::to_string(k);
    if (NumberAt(doc_, f + "/run") != run.id) continue;
    out_ +=
        "<h3>Fit</h3>\n<table class=\"fit\"><tr><th>residual RMS</th><th>noise σ</th><th>"
        "ratio</th><th>whiteness z</th><th>outliers removed</th><th>Ω offset [std]</th></tr>"
        "<tr><td>" +
        Src(f + "/residual_rms") + "</td><td>" + Src(f + "/noise_sigma") + "</td><td>" +
        Src(f + "/residual_ratio") + "</td><td>" + Src(f + "/whiteness_z") + "</td><td>" +
        Src(f + "/outliers_removed") + "</td><td>" + Src(f + "/omega_offset_in_std") +
        "</td></tr></table>\n";
  }
  if (run.loaded) {
    for (const char* kind : {"channels", "motion", "residuals", "orbit", "forms"})
      Figure(std::string(kind) + "-run-" + id, 960, 300);
  }
  out_ += "</section>\n";
}

}  // namespace hrgbench::report::internal
