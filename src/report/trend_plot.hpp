#pragma once
// One key parameter of a unit across its sessions as a small inline SVG (issue 26 §4: the unit's
// history as a trend, not only a table): one point per session, oldest left, this session last and
// filled, each with its bar of ± k·u where the session stored a std, and the limits this session
// was judged against as dashed lines. A drifting or repaired unit, or one creeping towards a
// limit, shows at a glance. At most kMaxUnitHistoryRows + 1 points: bounded whatever the history.
// Internal to src/report. Pure.

#include <optional>
#include <string>
#include <vector>

namespace hrgbench::report::internal {

struct TrendPoint {
  std::string label;          // the session's start (UTC), for the point's tooltip
  double value = 0.0;         // NaN: the session did not determine it (no point)
  double std_dev = 0.0;       // NaN: not stored (no bar)
  bool this_session = false;  // drawn filled
};

// `<svg class="trend" data-quantity="NAME" data-points="N" ...>`: a <circle class="session"> per
// point with a value, a <line class="uncertainty"> per point with a std, a <line class="limit">
// per finite limit, a <title> naming the quantity, k and the limits. Empty when no point has a
// value. `k` ≥ 0 (the coverage factor of the bars; 0 or not finite: no bars).
std::string TrendPlot(const std::string& quantity, const std::string& label,
                      const std::vector<TrendPoint>& points, double k,
                      std::optional<double> limit_min, std::optional<double> limit_max);

}  // namespace hrgbench::report::internal
