#pragma once
// The rate table's link state machine and its guard, shared by every hw::RateTable this project has
// (ModbusRateTable, and the in-process table of drivers/sim_station, which promises the same
// observable semantics): a call before Connect is kNotConnected; a motion command while a fault or
// e-stop is latched is kFaulted (stops, status reads, heartbeats and fault resets stay allowed).

#include <expected>
#include <string_view>

#include "hrgbench/hw/rate_table.hpp"

namespace hrgbench::drivers::modbus_rate_table {

enum class TableLinkState { kDisconnected, kConnected, kFaulted };
const char* TableLinkStateName(TableLinkState state);

// OK when a call may go ahead in `state`; `allow_faulted` for the calls a faulted table still
// takes. `table` names the table in the message ("rate table tcp 127.0.0.1:1502", ...).
std::expected<void, hw::RateTableError> RequireLinkState(TableLinkState state, bool allow_faulted,
                                                         std::string_view table);

}  // namespace hrgbench::drivers::modbus_rate_table
