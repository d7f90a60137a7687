#pragma once
// The table brought to stable at the rate it was commanded to, as every step that moves it waits
// (the sequencer's runs, the tuning's holds; internal to the bench): hw::RateTable::WaitUntilStable
// in slices of one dwell and half a second, so that a stop request is seen within one slice (on a
// table the dwell restarts with each slice, so a slice is the dwell plus this), until the timeout.
// Owner thread only; `stopped` and `between` are called between slices.

#include <functional>
#include <string>

#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::bench::internal {

inline constexpr double kTableWaitSliceS = 0.5;

enum class TableSettle { kStable, kStopped, kTimedOut, kTableError };

struct TableSettleResult {
  TableSettle end = TableSettle::kTimedOut;
  std::string table_error;  // kTableError: the table's own error, as it says it
};

// `criteria`'s tolerance, dwell and poll period (its timeout is the slice's); `timeout_s` in all.
TableSettleResult WaitTableSettled(hw::RateTable& table, const hw::Clock& clock,
                                   hw::StableCriteria criteria, double timeout_s,
                                   const std::function<bool()>& stopped,
                                   const std::function<void()>& between = {});

}  // namespace hrgbench::bench::internal
