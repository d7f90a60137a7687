#include "bench/sequencer/table_settle.hpp"

#include <algorithm>

namespace hrgbench::bench::internal {

TableSettleResult WaitTableSettled(hw::RateTable& table, const hw::Clock& clock,
                                   hw::StableCriteria criteria, double timeout_s,
                                   const std::function<bool()>& stopped,
                                   const std::function<void()>& between) {
  const std::int64_t deadline_ns = clock.NowNs() + hw::SecondsToNs(timeout_s);
  for (;;) {
    if (stopped && stopped()) return {TableSettle::kStopped, {}};
    const double left_s = static_cast<double>(deadline_ns - clock.NowNs()) * 1e-9;
    if (left_s <= 0.0) return {TableSettle::kTimedOut, {}};
    criteria.timeout_s =
        std::max(std::min(left_s, criteria.dwell_s + kTableWaitSliceS), criteria.dwell_s);
    auto stable = table.WaitUntilStable(criteria);
    if (stable) return {TableSettle::kStable, {}};
    if (stable.error().code != hw::RateTableErrorCode::kNotStable)
      return {TableSettle::kTableError, stable.error().ToString()};
    if (between) between();
  }
}

}  // namespace hrgbench::bench::internal
