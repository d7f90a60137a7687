#include "hrgbench/analysis/recorded_estimate.hpp"

#include <utility>

#include "hrgbench/analysis/estimate_report_json.hpp"
#include "hrgbench/analysis/output_filter.hpp"
#include "hrgbench/analysis/recorded_runs.hpp"
#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::bench {

RecordedEstimate EstimateRecordedSession(session::Session&& recorded,
                                         const session::SessionRecord& record,
                                         const estimator::FitQualityLimits& fit_quality,
                                         int threads) {
  RecordedEstimate out;
  MethodRequest request;
  request.fit_quality = fit_quality;  // the estimator warns as the verdict judges
  request.threads = threads;
  auto noise_shape = RecordedNoiseShape(record.electronics, recorded.sample_rate_hz);
  out.warnings = recorded.warnings;
  // The runs as every fit of a record takes them (recorded_runs.hpp).
  const PreparedRuns prepared = PrepareRecordedRuns(std::move(recorded), record.electronics);
  if (noise_shape) {
    request.noise_shape = std::move(*noise_shape);
    out.method = RunMethod(prepared.runs, request);
    NameIqConventionContradiction(record, &out.method.summary);
  } else {
    out.method.summary.termination = estimator::Termination::kInvalidInput;
    out.method.summary.message = noise_shape.error();
  }
  out.warnings.insert(out.warnings.end(), out.method.selection_warnings.begin(),
                      out.method.selection_warnings.end());
  out.report = EstimateReportJson("ml", out.method.summary, out.warnings, record);
  out.report["preparation"] = prepared.Json();
  // What the report needs to draw this fit without re-running it (estimate_report_json.hpp).
  out.report[session::keys::kFittedRuns] = FittedRunsJson(out.method.summary);
  return out;
}

RecordedEstimate EstimateRecordedSession(const session::Session& recorded,
                                         const session::SessionRecord& record,
                                         const estimator::FitQualityLimits& fit_quality) {
  session::Session copy = recorded;
  return EstimateRecordedSession(std::move(copy), record, fit_quality);
}

}  // namespace hrgbench::bench
