#pragma once
// The bench's estimate of a recorded session: maximum likelihood over the runs the record holds as
// complete, with the noise shape the record declares and the limits' fit thresholds. The sequencer
// makes it at the end of every session (so the verdict is about exactly what the record holds);
// `hrg-bench replay` makes it again from the samples the raw CAN log rebuilds, and the two must be
// the same bit for bit.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/analysis/estimate_method.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::bench {

struct RecordedEstimate {
  // The estimator's answer; termination kInvalidInput (with the reason) when the record's noise
  // shape cannot be read.
  MethodResult method;
  // The session reader's warnings, then the method selection's (the estimator's own are in
  // method.summary.warnings).
  std::vector<std::string> warnings;
  nlohmann::json report;  // EstimateReportJson("ml", ...): session.json outcome.estimate
};

// `recorded` must have its complete runs loaded (session::ReadSession with load_samples; its
// extra columns are not needed: ReadOptions::extra_columns = false); its samples are taken out
// (they are moved into the fit, never copied: docs/estimator/methods.md "Memory");
// `record` is the same session.json typed (session::ReadSessionRecord(recorded.document, file)):
// the electronics' declaration, the runs' plans and f0, the simulator's truth.
// `threads`: the estimator's (0: the hardware's; an interim look running beside the capture takes
// one).
RecordedEstimate EstimateRecordedSession(session::Session&& recorded,
                                         const session::SessionRecord& record,
                                         const estimator::FitQualityLimits& fit_quality,
                                         int threads = 0);
// The same on a copy of the samples, for a caller that keeps them (tests): twice the memory.
RecordedEstimate EstimateRecordedSession(const session::Session& recorded,
                                         const session::SessionRecord& record,
                                         const estimator::FitQualityLimits& fit_quality);

}  // namespace hrgbench::bench
