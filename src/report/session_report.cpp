#include "hrgbench/report/session_report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "external_outputs.hpp"
#include "hrgbench/analysis/estimate_method.hpp"
#include "hrgbench/analysis/estimate_report_json.hpp"
#include "hrgbench/analysis/output_filter.hpp"
#include "hrgbench/analysis/recorded_runs.hpp"
#include "hrgbench/estimator/fitted_output.hpp"
#include "hrgbench/estimator/model.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"
#include "html_page.hpp"
#include "html_text.hpp"
#include "parallel_runs.hpp"
#include "report_data.hpp"
#include "report_inputs.hpp"
#include "tune_data.hpp"

namespace hrgbench::report {

std::string_view ToString(PaperSize paper) noexcept {
  return paper == PaperSize::kLetter ? "letter" : "a4";
}

std::optional<PaperSize> ParsePaperSize(std::string_view text) noexcept {
  if (text == "a4") return PaperSize::kA4;
  if (text == "letter") return PaperSize::kLetter;
  return std::nullopt;
}

std::string ReportError::ToString() const {
  std::string text = file.string();
  if (!field.empty()) text += ": field '" + field + "'";
  return text + ": " + message;
}

namespace {

using internal::ReportInputs;
using internal::RunView;
using nlohmann::json;
namespace fs = std::filesystem;

// Chart.js is ~200 KB; anything over this is not the file we mean.
constexpr std::uintmax_t kMaxChartJsBytes = std::uintmax_t{8} << 20;

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::expected<std::string, ReportError> LoadChartJs(const fs::path& requested) {
  std::vector<fs::path> candidates;
  if (!requested.empty())
    candidates.push_back(requested);
  else
    for (const char* c : kChartJsCandidates) candidates.emplace_back(c);
  for (const fs::path& path : candidates) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) continue;
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec || size > kMaxChartJsBytes)
      return std::unexpected(ReportError{path, "", "not a Chart.js build (over 8 MiB)"});
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    std::string script = text.str();
    if (script.find("Chart") == std::string::npos)
      return std::unexpected(ReportError{path, "", "does not define Chart"});
    if (!internal::ScriptSafeJavaScript(&script))
      return std::unexpected(ReportError{path, "", "contains </script> and cannot be inlined"});
    return script;
  }
  return std::unexpected(
      ReportError{requested.empty() ? fs::path(kChartJsCandidates[1]) : requested, "",
                  "Chart.js (UMD build) not found: install Debian's libjs-chart.js "
                  "(scripts/setup-debian.sh) or give its path"});
}

void AddWarning(std::vector<std::string>* warnings, std::set<std::string>* seen,
                const std::string& text) {
  if (seen->insert(text).second) warnings->push_back(text);
}

// The fit-quality limits the bench judged with, as recorded under outcome.estimate.fit.limits.
estimator::FitQualityLimits RecordedFitLimits(const session::SessionRecord& record) {
  estimator::FitQualityLimits limits;
  if (!record.outcome || !record.outcome->estimate) return limits;
  const session::EstimateRecord& estimate = *record.outcome->estimate;
  estimator::FitQualityLimits recorded = limits;
  if (std::isfinite(estimate.fit_residual_ratio_max))
    recorded.residual_ratio_max = estimate.fit_residual_ratio_max;
  if (std::isfinite(estimate.fit_whiteness_z_max))
    recorded.whiteness_z_max = estimate.fit_whiteness_z_max;
  if (std::isfinite(estimate.fit_omega_offset_max_in_std))
    recorded.omega_offset_max_in_std = estimate.fit_omega_offset_max_in_std;
  return recorded.IsValid(nullptr) ? recorded : limits;
}

// The estimate of record as a summary the drawing code takes: δ, ξ, their std, σ̂ and each run's
// nuisance (what FittedState needs), the rest as recorded. nullopt when its δ/ξ are not all
// finite (an estimate that failed).
std::optional<estimator::EstimateSummary> RecordedSummary(const session::SessionRecord& record) {
  if (!record.outcome || !record.outcome->estimate) return std::nullopt;
  const session::EstimateRecord& e = *record.outcome->estimate;
  estimator::EstimateSummary s;
  s.method = e.method;
  s.message = "the estimate of record (session.json outcome.estimate)";
  for (const auto t :
       {estimator::Termination::kConverged, estimator::Termination::kMaxIterations,
        estimator::Termination::kNoProgress, estimator::Termination::kInvalidInput,
        estimator::Termination::kNotIdentifiable, estimator::Termination::kNumericalFailure}) {
    if (e.termination == estimator::ToString(t)) s.termination = t;
  }
  for (int i = 0; i < 6; ++i) {
    s.delta[i] = e.delta[static_cast<std::size_t>(i)];
    s.delta_std[i] = e.delta_std[static_cast<std::size_t>(i)];
    s.delta_estimated[static_cast<std::size_t>(i)] = std::isfinite(s.delta_std[i]);
  }
  for (int i = 0; i < 4; ++i) {
    s.xi[i] = e.xi[static_cast<std::size_t>(i)];
    s.xi_std[i] = e.xi_std[static_cast<std::size_t>(i)];
    s.xi_estimated[static_cast<std::size_t>(i)] = std::isfinite(s.xi_std[i]);
  }
  if (!s.delta.allFinite() || !s.xi.allFinite()) return std::nullopt;
  s.residual_rms = e.residual_rms;
  s.noise_sigma = e.noise_sigma;
  s.iterations = e.iterations;
  s.samples_used = static_cast<std::size_t>(std::max<std::int64_t>(e.samples_used, 0));
  s.diagnostics.phase_degree = e.phase_degree;
  s.warnings = e.warnings;
  for (const session::FittedRunRecord& run : e.fitted_runs) {
    estimator::RunNuisanceEstimate n;
    n.run_id = run.run_id;
    n.initial_state = Eigen::Vector4d(run.initial_state.data());
    n.phase_coefficients = run.phase_coefficients;
    n.omega_offset_rad_s = run.omega_offset_rad_s;
    s.initial_states.push_back(n.initial_state);
    s.run_nuisance.push_back(std::move(n));
  }
  return s;
}

// The run CSV's header names a conditions column (temp_c or freq_hz: the electronics' status per
// sample). Only then are its extra columns kept: the others (seq, the table's rate) are not drawn.
bool HasConditionsColumn(const fs::path& csv) {
  std::ifstream in(csv, std::ios::binary);
  std::string header(4096, '\0');
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  header.resize(static_cast<std::size_t>(in.gcount()));
  header = header.substr(0, header.find('\n'));
  if (!header.empty() && header.back() == '\r') header.pop_back();
  for (const std::string column : {"temp_c", "freq_hz"}) {
    for (std::size_t at = header.find(column); at != std::string::npos;
         at = header.find(column, at + 1)) {
      const bool starts = at == 0 || header[at - 1] == ',';
      const bool ends = at + column.size() == header.size() || header[at + column.size()] == ',';
      if (starts && ends) return true;
    }
  }
  return false;
}

// Reads run `v`'s samples (t_s and y; the extra columns are not drawn) in the model's I/Q
// convention, as the bench fits (recorded_runs.hpp). False, and `why` set, when it cannot be read.
bool LoadRunSamples(const fs::path& session_dir, const session::SessionRecord& record,
                    std::size_t min_samples, RunView* v, std::string* why) {
  auto samples = session::ReadRunCsv(session_dir / v->file, min_samples,
                                     HasConditionsColumn(session_dir / v->file));
  if (!samples) {
    std::error_code ec;
    const bool exists = fs::exists(session_dir / v->file, ec);
    *why = (exists ? "cannot be read: " : "its file is missing: ") + samples.error().ToString();
    return false;
  }
  v->loaded = true;
  v->samples = samples->t_s.size();
  v->first_t_s = samples->t_s.empty() ? 0.0 : samples->t_s.front();
  v->last_t_s = samples->t_s.empty() ? 0.0 : samples->t_s.back();
  if (const auto t = samples->extra_columns.find("temp_c"); t != samples->extra_columns.end())
    v->temperature_c = std::move(t->second);
  if (const auto f = samples->extra_columns.find("freq_hz"); f != samples->extra_columns.end())
    v->resonant_frequency_hz = std::move(f->second);
  v->data.t_s = std::move(samples->t_s);
  v->data.y = std::move(samples->y);
  estimator::ToModelConvention(record.iq_convention, v->data.y);
  return true;
}

// Run `v`'s part of the page while its samples are in memory: x̂ once, ŷ = (I + C(ξ̂))·x̂ from it
// (what FittedOutput computes, in one pass) when `drawn` is given, the capture quality and the
// figures; then the samples and the fitted model are dropped, so the report holds one run's
// samples per thread, never the session's.
internal::RunPart FinishRun(RunView* v, const estimator::EstimateSummary* drawn,
                            const ReportInputs& in, std::size_t max_points) {
  if (drawn != nullptr) {
    const Eigen::Matrix4d distortion =
        Eigen::Matrix4d::Identity() + estimator::DistortionMatrix(drawn->xi);
    v->fitted_x = estimator::FittedState(*drawn, v->data);
    v->fitted_y = v->fitted_x * distortion.transpose();
  }
  const estimator::Xi xi = in.summary ? in.summary->xi : estimator::Xi::Zero();
  const double sigma = in.summary ? in.summary->noise_sigma : estimator::kNaN;
  internal::RunPart part = internal::BuildRunPart(*v, in.record, xi, sigma, max_points);
  v->data.t_s = std::vector<double>();
  v->temperature_c = std::vector<double>();
  v->resonant_frequency_hz = std::vector<double>();
  v->data.y.resize(4, 0);
  v->fitted_x.resize(0, 4);
  v->fitted_y.resize(0, 4);
  return part;
}

// The runs drawn with figures: every run when there are at most `max`; else the first, the last
// and the worst by residual RMS (the recorded fit's, or the re-run's) up to `max`, evenly spaced
// ones where residuals are not known. `ids`: the complete runs, in record order.
std::set<int> RunsWithFigures(const std::vector<int>& ids, const std::map<int, double>& residual,
                              std::size_t max) {
  std::set<int> chosen;
  if (ids.size() <= max) return {ids.begin(), ids.end()};
  if (max == 0) return chosen;
  chosen.insert(ids.front());
  if (max >= 2) chosen.insert(ids.back());
  std::vector<std::pair<double, int>> ranked;
  for (const int id : ids)
    if (const auto it = residual.find(id); it != residual.end() && std::isfinite(it->second))
      ranked.emplace_back(it->second, id);
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  for (const auto& [rms, id] : ranked) {
    if (chosen.size() >= max) break;
    chosen.insert(id);
  }
  for (std::size_t k = 0; chosen.size() < max && k < max; ++k)
    chosen.insert(ids[k * (ids.size() - 1) / (max - 1)]);
  for (std::size_t k = 0; chosen.size() < max && k < ids.size(); ++k) chosen.insert(ids[k]);
  return chosen;
}

void MarkRunsWithFigures(ReportInputs* in, const std::map<int, double>& residual, std::size_t max) {
  std::vector<int> ids;
  for (const RunView& v : in->runs)
    if (v.status == bench::kRunComplete) ids.push_back(v.id);
  const std::set<int> chosen = RunsWithFigures(ids, residual, max);
  for (RunView& v : in->runs) v.figures = chosen.contains(v.id);
}

// Re-runs the estimate as the bench's EstimateAndClose does, and checks it against the record.
void Estimate(ReportInputs* in, const session::SessionRecord& record, std::set<std::string>* seen,
              const std::vector<std::string>& reader_warnings) {
  // The samples move into the fit (never a second copy); each run is read again to be drawn.
  std::vector<estimator::RunData> runs;
  for (RunView& v : in->runs)
    if (v.loaded) runs.push_back(std::move(v.data));
  if (runs.empty()) {
    AddWarning(&in->warnings, seen, "no run could be loaded: nothing estimated or drawn");
    return;
  }
  bench::MethodRequest request;
  request.fit_quality = RecordedFitLimits(record);
  if (auto shape = bench::RecordedNoiseShape(record.electronics, in->sample_rate_hz); shape) {
    request.noise_shape = std::move(*shape);
  } else {
    AddWarning(&in->warnings, seen,
               "the record's noise shape is unusable (" + shape.error() +
                   "): the report's checks assume white noise");
  }
  // Less the output filter's settling after release, as the bench fits (recorded_runs.hpp).
  bench::SkipReleaseSettling(
      bench::ReleaseSettlingS(bench::RecordedOutputFilter(record.electronics)), &runs);
  bench::MethodResult estimated = bench::RunMethod(runs, request);
  std::vector<std::string> warnings = reader_warnings;
  warnings.insert(warnings.end(), estimated.selection_warnings.begin(),
                  estimated.selection_warnings.end());
  in->estimate_json = bench::EstimateReportJson("ml", estimated.summary, warnings, record);
  for (const std::string& w : estimated.selection_warnings) AddWarning(&in->warnings, seen, w);
  for (const std::string& w : estimated.summary.warnings) AddWarning(&in->warnings, seen, w);
  if (!estimated.summary.IsUsable()) {
    AddWarning(&in->warnings, seen,
               "the report's estimate is not usable (" + estimated.summary.message +
                   "): no fitted model drawn");
  } else {
    // The model drawn is the re-run's: say so if it is not the one recorded.
    for (int p = 0; p < 10; ++p) {
      const bool is_delta = p < 6;
      const int i = is_delta ? p : p - 6;
      const std::string key = is_delta ? "delta" : "xi";
      const session::EstimateRecord* of_record =
          record.outcome && record.outcome->estimate ? &*record.outcome->estimate : nullptr;
      const double recorded = of_record == nullptr ? std::nan("")
                              : is_delta           ? of_record->delta[static_cast<std::size_t>(i)]
                                                   : of_record->xi[static_cast<std::size_t>(i)];
      const double now = is_delta ? estimated.summary.delta[i] : estimated.summary.xi[i];
      const double sd = is_delta ? estimated.summary.delta_std[i] : estimated.summary.xi_std[i];
      if (!std::isfinite(recorded) || !std::isfinite(sd) || !(sd > 0.0)) continue;
      if (std::abs(recorded - now) > 1e-3 * sd) {
        AddWarning(&in->warnings, seen,
                   "the report's re-run estimate of " + key + std::to_string(i + 1) +
                       " differs from the recorded one by " +
                       internal::Readable(std::abs(recorded - now) / sd) +
                       " std: the fitted model drawn is the re-run's");
      }
    }
  }
  in->summary = std::move(estimated.summary);
}

}  // namespace

std::expected<ReportResult, ReportError> WriteSessionReport(const fs::path& session_dir,
                                                            const ReportOptions& options) {
  ReportResult result;
  auto chart_js = LoadChartJs(options.chart_js);
  if (!chart_js) return std::unexpected(chart_js.error());

  auto start = std::chrono::steady_clock::now();
  const auto record = session::ReadSessionRecord(session_dir);
  if (!record)
    return std::unexpected(
        ReportError{record.error().file, record.error().field, record.error().message});
  ReportInputs in;
  in.session_dir = session_dir;
  in.record = *record;
  in.sample_rate_hz = record->sample_rate_hz;
  in.unit_history = options.unit_history;
  in.paper = options.paper;
  std::set<std::string> seen;
  std::vector<std::string> reader_warnings;
  for (const std::string& w : record->warnings) {
    AddWarning(&in.warnings, &seen, w);
    reader_warnings.push_back(w);
  }
  {
    internal::TuneRead tune = internal::ReadTuneRecord(session_dir);
    in.tune = std::move(tune.record);
    if (!tune.warning.empty()) AddWarning(&in.warnings, &seen, "tuning not shown: " + tune.warning);
  }
  const std::size_t min_samples = bench::MinimumSamples(bench::Method::kMl);
  // The recorded fit is drawn as recorded; the estimator runs only when asked or when the record
  // keeps no fitted runs (it was recorded before they were kept, or has no estimate of record).
  const session::EstimateRecord* of_record =
      record->outcome && record->outcome->estimate ? &*record->outcome->estimate : nullptr;
  const bool rerun = options.refit || of_record == nullptr || !of_record->fitted_runs_recorded;
  for (std::size_t i = 0; i < record->runs.size(); ++i) {
    const session::RunRecord& entry = record->runs[i];
    RunView v;
    v.id = entry.id;
    v.index = i;
    v.status = entry.status;
    v.file = entry.file;
    v.data.id = entry.id;
    v.data.omega_rad_s = entry.omega_rad_s;
    // The standard error of Ω when the bench measured it (NaN: not measured, or a run ended by a
    // recorder error).
    v.data.omega_std_rad_s =
        entry.end ? entry.end->values.omega_std_error_rad_s : session::kNotRecorded;
    if (entry.status != bench::kRunComplete) v.not_loaded_reason = "status '" + entry.status + "'";
    in.runs.push_back(std::move(v));
  }
  const estimator::EstimateSummary* drawn = nullptr;
  if (!rerun) {
    in.estimate_json = record->outcome->estimate_json;
    in.summary = RecordedSummary(*record);
    if (in.summary && in.summary->IsUsable()) drawn = &*in.summary;
    std::map<int, double> residual;
    for (const session::FitRunRecord& fit : of_record->fit_runs)
      residual[fit.run] = fit.residual_rms;
    MarkRunsWithFigures(&in, residual, options.max_runs_with_figures);
  }
  // Every complete run read, one run per thread at a time; drawn at once when the recorded fit is
  // drawn, kept for the estimate otherwise.
  std::vector<internal::RunPart> parts(in.runs.size());
  std::vector<std::string> read_errors(in.runs.size());
  internal::ParallelRuns(in.runs.size(), [&](std::size_t r) {
    RunView& v = in.runs[r];
    if (v.status != bench::kRunComplete) return;
    if (!LoadRunSamples(session_dir, *record, min_samples, &v, &read_errors[r])) return;
    if (!rerun) parts[r] = FinishRun(&v, drawn, in, options.max_points_per_series);
  });
  for (std::size_t r = 0; r < in.runs.size(); ++r) {
    RunView& v = in.runs[r];
    const std::string& why = read_errors[r];
    if (why.empty()) continue;
    v.not_loaded_reason = why;
    const std::string w =
        "run " + std::to_string(v.id) + ": not estimated and not drawn, " + v.not_loaded_reason;
    AddWarning(&in.warnings, &seen, w);
    reader_warnings.push_back(w);
  }
  if (!record->outcome)
    AddWarning(&in.warnings, &seen,
               "session.json has no outcome: not recorded by a bench session that closed (an "
               "hrg-sim session or an older format); outcome, verdict and engineering quantities "
               "not shown");
  if (record->outcome && record->outcome->estimate)
    for (const std::string& w : record->outcome->estimate->warnings)
      AddWarning(&in.warnings, &seen, w);
  result.read_s = Since(start);

  start = std::chrono::steady_clock::now();
  if (!rerun) {
    if (drawn == nullptr)
      AddWarning(&in.warnings, &seen,
                 "the estimate of record is not usable: no fitted model drawn (hrg-report --refit "
                 "re-runs it)");
  } else {
    if (!options.refit && of_record != nullptr)
      AddWarning(&in.warnings, &seen,
                 "the record's estimate keeps no fitted runs (recorded before they were kept): the "
                 "report re-runs the estimate to draw the fitted model");
    Estimate(&in, *record, &seen, reader_warnings);
    result.estimate_rerun = true;
    if (in.summary && in.summary->IsUsable()) drawn = &*in.summary;
    std::map<int, double> residual;
    if (in.summary)
      for (std::size_t r = 0;
           r < in.summary->run_nuisance.size() && r < in.summary->residual_rms_per_run.size(); ++r)
        residual[in.summary->run_nuisance[r].run_id] = in.summary->residual_rms_per_run[r];
    MarkRunsWithFigures(&in, residual, options.max_runs_with_figures);
    // The estimate took the samples: each run is read again to be drawn, one at a time.
    internal::ParallelRuns(in.runs.size(), [&](std::size_t r) {
      RunView& v = in.runs[r];
      if (!v.loaded) return;
      std::string why;
      if (LoadRunSamples(session_dir, *record, min_samples, &v, &why)) {
        parts[r] = FinishRun(&v, drawn, in, options.max_points_per_series);
      } else {  // changed since it was estimated: said in its section, not drawn
        v.loaded = false;
        v.not_loaded_reason = why;
      }
    });
  }
  result.estimate_s = Since(start);

  start = std::chrono::steady_clock::now();
  const json data = internal::BuildReportData(in, std::move(parts));
  const fs::path html =
      options.output.empty() ? session_dir / "report" / "report.html" : options.output;
  const fs::path out_dir = html.parent_path().empty() ? fs::path(".") : html.parent_path();
  if (auto made = session::CreateDirectoriesDurably(out_dir); !made)
    return std::unexpected(ReportError{out_dir, "", made.error().message});
  result.page_s = Since(start);

  if (options.figures) {
    start = std::chrono::steady_clock::now();
    internal::FiguresResult figures =
        internal::WriteGnuplotFigures(data, out_dir, options.child_timeout_s);
    result.figures = std::move(figures.written);
    for (const std::string& w : figures.warnings) AddWarning(&in.warnings, &seen, w);
    result.figures_s = Since(start);
  }

  start = std::chrono::steady_clock::now();
  const std::string page = internal::RenderHtml(in, data, *chart_js);
  if (auto written = session::WriteFileAtomic(html, page); !written)
    return std::unexpected(ReportError{html, "", written.error().ToString()});
  result.html = html;
  result.html_bytes = page.size();
  result.page_s += Since(start);
  result.warnings = in.warnings;

  if (options.pdf) {
    start = std::chrono::steady_clock::now();
    std::string chromium = options.chromium;
    if (chromium.empty()) {
      const char* env = std::getenv("HRGBENCH_CHROMIUM");
      chromium = env != nullptr && *env != '\0' ? env : "chromium";
    }
    const fs::path pdf = out_dir / (html.stem().string() + ".pdf");
    const std::string why = internal::PrintPdf(chromium, html, pdf, options.child_timeout_s);
    if (why.empty())
      result.pdf = pdf;
    else
      result.warnings.push_back("no PDF: " + why + " (the HTML report stands)");
    result.pdf_s = Since(start);
  }
  return result;
}

}  // namespace hrgbench::report
