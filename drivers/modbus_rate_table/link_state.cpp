#include "modbus_rate_table/link_state.hpp"

#include <string>

namespace hrgbench::drivers::modbus_rate_table {

const char* TableLinkStateName(TableLinkState state) {
  switch (state) {
    case TableLinkState::kDisconnected:
      return "disconnected";
    case TableLinkState::kConnected:
      return "connected";
    case TableLinkState::kFaulted:
      return "faulted";
  }
  return "unknown";
}

std::expected<void, hw::RateTableError> RequireLinkState(TableLinkState state, bool allow_faulted,
                                                         std::string_view table) {
  switch (state) {
    case TableLinkState::kDisconnected:
      return std::unexpected(
          hw::RateTableError{hw::RateTableErrorCode::kNotConnected,
                             std::string(table) + " is not connected (call Connect)"});
    case TableLinkState::kFaulted:
      if (!allow_faulted) {
        return std::unexpected(hw::RateTableError{
            hw::RateTableErrorCode::kFaulted,
            "rate table is faulted; ResetFault() and read a clean status first"});
      }
      break;
    case TableLinkState::kConnected:
      break;
  }
  return {};
}

}  // namespace hrgbench::drivers::modbus_rate_table
