#include "hrgbench/report/session_report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "external_outputs.hpp"
#include "hrgbench/bench/estimate_method.hpp"
#include "hrgbench/bench/estimate_report_json.hpp"
#include "hrgbench/bench/output_filter.hpp"
#include "hrgbench/bench/recorded_runs.hpp"
#include "hrgbench/estimator/fitted_output.hpp"
#include "hrgbench/estimator/model.hpp"
#include "hrgbench/session/session.hpp"
#include "html_page.hpp"
#include "html_text.hpp"
#include "parallel_runs.hpp"
#include "report_data.hpp"
#include "report_inputs.hpp"

namespace hrgbench::report {

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
estimator::FitQualityLimits RecordedFitLimits(const json& document) {
  estimator::FitQualityLimits limits;
  const std::string base = "/outcome/estimate/fit/limits/";
  const double ratio = internal::NumberAt(document, base + "residual_ratio_max");
  const double whiteness = internal::NumberAt(document, base + "whiteness_z_max");
  const double offset = internal::NumberAt(document, base + "omega_offset_max_in_std");
  estimator::FitQualityLimits recorded = limits;
  if (std::isfinite(ratio)) recorded.residual_ratio_max = ratio;
  if (std::isfinite(whiteness)) recorded.whiteness_z_max = whiteness;
  if (std::isfinite(offset)) recorded.omega_offset_max_in_std = offset;
  return recorded.IsValid(nullptr) ? recorded : limits;
}

// Re-runs the estimate as the bench's EstimateAndClose does, and checks it against the record.
void Estimate(ReportInputs* in, std::set<std::string>* seen,
              const std::vector<std::string>& reader_warnings) {
  std::vector<estimator::RunData> runs;
  for (const RunView& v : in->runs)
    if (v.loaded) runs.push_back(v.data);
  if (runs.empty()) {
    AddWarning(&in->warnings, seen, "no run could be loaded: nothing estimated or drawn");
    return;
  }
  bench::MethodRequest request;
  request.fit_quality = RecordedFitLimits(in->document);
  if (auto shape = bench::RecordedNoiseShape(in->document, in->sample_rate_hz); shape) {
    request.noise_shape = std::move(*shape);
  } else {
    AddWarning(&in->warnings, seen,
               "the record's noise shape is unusable (" + shape.error() +
                   "): the report's checks assume white noise");
  }
  // Less the output filter's settling after release, as the bench fits (recorded_runs.hpp).
  if (auto filter = bench::RecordedOutputFilter(in->document); filter)
    bench::SkipReleaseSettling(bench::ReleaseSettlingS(*filter), &runs);
  bench::MethodResult estimated = bench::RunMethod(runs, request);
  std::vector<std::string> warnings = reader_warnings;
  warnings.insert(warnings.end(), estimated.selection_warnings.begin(),
                  estimated.selection_warnings.end());
  in->estimate_json = bench::EstimateReportJson("ml", estimated.summary, warnings, in->document);
  for (const std::string& w : estimated.selection_warnings) AddWarning(&in->warnings, seen, w);
  for (const std::string& w : estimated.summary.warnings) AddWarning(&in->warnings, seen, w);
  if (!estimated.summary.IsUsable()) {
    AddWarning(&in->warnings, seen,
               "the report's estimate is not usable (" + estimated.summary.message +
                   "): no fitted model drawn");
  } else {
    // x̂ once per run, ŷ = (I + C(ξ̂))·x̂ from it (what FittedOutput computes, in one pass).
    const Eigen::Matrix4d distortion =
        Eigen::Matrix4d::Identity() + estimator::DistortionMatrix(estimated.summary.xi);
    internal::ParallelRuns(in->runs.size(), [&](std::size_t r) {
      RunView& v = in->runs[r];
      if (!v.loaded) return;
      v.fitted_x = estimator::FittedState(estimated.summary, v.data);
      v.fitted_y = v.fitted_x * distortion.transpose();
    });
    // The model drawn is the re-run's: say so if it is not the one recorded.
    for (int p = 0; p < 10; ++p) {
      const bool is_delta = p < 6;
      const int i = is_delta ? p : p - 6;
      const std::string key = is_delta ? "delta" : "xi";
      const double recorded =
          internal::NumberAt(in->document, "/outcome/estimate/" + key + "/" + std::to_string(i));
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
  session::ReadOptions read;
  read.load_samples = false;
  const auto session = session::ReadSession(session_dir, read);
  if (!session)
    return std::unexpected(
        ReportError{session.error().file, session.error().field, session.error().message});
  ReportInputs in;
  in.session_dir = session_dir;
  in.document = session->document;
  in.sample_rate_hz = session->sample_rate_hz;
  in.unit_history = options.unit_history;
  std::set<std::string> seen;
  std::vector<std::string> reader_warnings;
  for (const std::string& w : session->warnings) {
    AddWarning(&in.warnings, &seen, w);
    reader_warnings.push_back(w);
  }
  const std::size_t min_samples = bench::MinimumSamples(bench::Method::kMl);
  for (std::size_t i = 0; i < session->runs.size(); ++i) {
    const session::RunEntry& entry = session->runs[i];
    RunView v;
    v.id = entry.id;
    v.index = i;
    v.status = entry.status;
    v.file = entry.file;
    if (entry.status != "complete") {
      v.not_loaded_reason = "status '" + entry.status + "'";
    } else {
      auto samples = session::ReadRunCsv(session_dir / entry.file, min_samples);
      if (!samples) {
        std::error_code ec;
        const bool exists = fs::exists(session_dir / entry.file, ec);
        v.not_loaded_reason =
            (exists ? "cannot be read: " : "its file is missing: ") + samples.error().ToString();
        const std::string w = "run " + std::to_string(entry.id) +
                              ": not estimated and not drawn, " + v.not_loaded_reason;
        AddWarning(&in.warnings, &seen, w);
        reader_warnings.push_back(w);
      } else {
        v.loaded = true;
        v.data.id = entry.id;
        v.data.omega_rad_s = entry.omega_rad_s;
        v.data.omega_std_rad_s = entry.omega_std_rad_s;
        v.data.t_s = std::move(samples->t_s);
        v.data.y = std::move(samples->y);
        // Drawn and fitted in the model's I/Q convention, as the bench fits (recorded_runs.hpp).
        estimator::ToModelConvention(session->iq_convention, v.data.y);
      }
    }
    in.runs.push_back(std::move(v));
  }
  if (!internal::At(in.document, "/outcome"))
    AddWarning(&in.warnings, &seen,
               "session.json has no outcome: not recorded by a bench session that closed (an "
               "hrg-sim session or an older format); outcome, verdict and engineering quantities "
               "not shown");
  if (const json* recorded = internal::At(in.document, "/outcome/estimate/warnings");
      recorded != nullptr && recorded->is_array())
    for (const json& w : *recorded)
      if (w.is_string()) AddWarning(&in.warnings, &seen, w.get<std::string>());
  result.read_s = Since(start);

  start = std::chrono::steady_clock::now();
  Estimate(&in, &seen, reader_warnings);
  result.estimate_s = Since(start);

  start = std::chrono::steady_clock::now();
  const json data = internal::BuildReportData(in, options.max_points_per_series);
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
