#include "sim/table_fault_rule.hpp"

#include <charconv>

namespace hrgbench::drivers::sim {

namespace {
bool ParseInt(std::string_view text, int* value) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), *value);
  return ec == std::errc() && end == text.data() + text.size();
}
}  // namespace

std::string FaultRule::ToString() const {
  std::string s = table == RegisterTable::kHolding ? "holding:" : "input:";
  s += std::to_string(address) + "=";
  switch (kind) {
    case FaultKind::kException:
      s += "exception";
      break;
    case FaultKind::kLateReply:
      s += "late";
      break;
    case FaultKind::kWrongLength:
      s += "wrong-length";
      break;
  }
  if (count >= 0) s += "*" + std::to_string(count);
  return s;
}

std::expected<FaultRule, std::string> ParseFaultRule(const std::string& text) {
  const auto bad = [&text](const std::string& why) {
    return std::unexpected("fault rule '" + text + "': " + why +
                           " (form: holding|input:<address>=exception|late|wrong-length[*n])");
  };
  const auto colon = text.find(':');
  const auto equals = text.find('=');
  if (colon == std::string::npos || equals == std::string::npos || equals < colon) {
    return bad("missing ':' or '='");
  }
  FaultRule rule;
  const std::string table = text.substr(0, colon);
  if (table == "holding") {
    rule.table = RegisterTable::kHolding;
  } else if (table == "input") {
    rule.table = RegisterTable::kInput;
  } else {
    return bad("unknown register table '" + table + "'");
  }
  if (!ParseInt(std::string_view(text).substr(colon + 1, equals - colon - 1), &rule.address) ||
      rule.address < 0 || rule.address > 65535) {
    return bad("address is not a number in 0..65535");
  }
  std::string kind = text.substr(equals + 1);
  if (const auto star = kind.find('*'); star != std::string::npos) {
    if (!ParseInt(std::string_view(kind).substr(star + 1), &rule.count) || rule.count < 1) {
      return bad("count after '*' must be a positive number");
    }
    kind.resize(star);
  }
  if (kind == "exception") {
    rule.kind = FaultKind::kException;
  } else if (kind == "late") {
    rule.kind = FaultKind::kLateReply;
  } else if (kind == "wrong-length") {
    rule.kind = FaultKind::kWrongLength;
  } else {
    return bad("unknown fault kind '" + kind + "'");
  }
  return rule;
}

}  // namespace hrgbench::drivers::sim
