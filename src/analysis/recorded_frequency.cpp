#include "hrgbench/analysis/recorded_frequency.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hrgbench::bench {

RecordedFrequency RecordedResonantFrequency(const session::SessionRecord& record) {
  RecordedFrequency out;
  double sum = 0.0, low = 0.0, high = 0.0;
  for (const session::RunRecord& run : record.runs) {
    if (run.status != bench::kRunComplete || !run.start) continue;
    const double hz = run.start->values.resonant_frequency_hz;
    if (!(std::isfinite(hz) && hz > 0.0)) continue;
    low = out.runs == 0 ? hz : std::min(low, hz);
    high = out.runs == 0 ? hz : std::max(high, hz);
    sum += hz;
    ++out.runs;
  }
  if (out.runs == 0) {
    out.source = "not recorded (no complete run has the electronics' resonant frequency)";
    return out;
  }
  out.hz = sum / out.runs;
  out.spread_hz = high - low;
  char text[160];
  std::snprintf(text, sizeof text, "electronics status at the release of %d run%s (spread %.6g Hz)",
                out.runs, out.runs == 1 ? "" : "s", out.spread_hz);
  out.source = text;
  return out;
}

}  // namespace hrgbench::bench
