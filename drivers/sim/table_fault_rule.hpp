#pragma once
// Fault injection for the simulated table's Modbus server, in the manner of libmodbus'
// tests/unit-test-server.c: a request whose register range covers a chosen register gets a chosen
// misbehaviour instead of (or before) the normal reply.
//
// Text form (CLI --fault-at, test logs): "<table>:<address>=<kind>[*<count>]"
//   table: holding | input;  kind: exception | late | wrong-length;  count: times (default: always)
//   e.g. "input:4=late*1", "holding:2=exception"

#include <cstdint>
#include <expected>
#include <string>

namespace hrgbench::drivers::sim {

enum class RegisterTable { kHolding, kInput };

enum class FaultKind {
  kException,    // Modbus exception reply (exception_code) instead of the answer
  kLateReply,    // the normal reply, sent after the server's late_reply_ms
  kWrongLength,  // reads only: a reply with one register fewer (or more) than asked
};

struct FaultRule {
  RegisterTable table = RegisterTable::kInput;
  int address = 0;
  FaultKind kind = FaultKind::kException;
  int count = -1;                   // replies left to spoil; -1 = every matching request
  std::uint8_t exception_code = 4;  // SERVER DEVICE FAILURE

  std::string ToString() const;
};

std::expected<FaultRule, std::string> ParseFaultRule(const std::string& text);

}  // namespace hrgbench::drivers::sim
