#include "hrgbench/analysis/recorded_frequency.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hrgbench::bench {

RecordedFrequency RecordedResonantFrequency(const nlohmann::json& session_document) {
  RecordedFrequency out;
  double sum = 0.0, low = 0.0, high = 0.0;
  // contains() + at() rather than find(): GCC's -Wnull-dereference sees a null in the
  // library's iterators.
  if (session_document.is_object() && session_document.contains("runs") &&
      session_document.at("runs").is_array()) {
    for (const nlohmann::json& run : session_document.at("runs")) {
      if (!run.is_object() || run.value("status", std::string()) != "complete") continue;
      if (!run.contains("start") || !run.at("start").is_object()) continue;
      const nlohmann::json& start = run.at("start");
      if (!start.contains("resonant_frequency_hz")) continue;
      const nlohmann::json& f = start.at("resonant_frequency_hz");
      if (!f.is_number()) continue;
      const double hz = f.get<double>();
      if (!(std::isfinite(hz) && hz > 0.0)) continue;
      low = out.runs == 0 ? hz : std::min(low, hz);
      high = out.runs == 0 ? hz : std::max(high, hz);
      sum += hz;
      ++out.runs;
    }
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
