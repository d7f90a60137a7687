#include "app/serial_check.hpp"

#include "hrgbench/config/toml_reader.hpp"

namespace hrgbench::app {
namespace {

bool Allowed(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '_' || c == '-';
}

// `what`: "the serial" or "the operator id", the sentence's subject.
std::optional<std::string> IdProblem(std::string_view serial, const std::string& what) {
  if (serial.empty()) return what + " is empty";
  if (serial.size() > kMaxSerialLength)
    return what + " is too long: " + std::to_string(serial.size()) + " characters, at most " +
           std::to_string(kMaxSerialLength);
  for (std::size_t i = 0; i < serial.size(); ++i) {
    const auto c = static_cast<unsigned char>(serial[i]);
    if (c < 0x20 || c == 0x7f)
      return what + " contains a control character (code " + std::to_string(c) + ") at position " +
             std::to_string(i + 1);
    if (!Allowed(serial[i]))
      return what + " contains '" + (c < 0x80 ? std::string(1, serial[i]) : "?") +
             "' at position " + std::to_string(i + 1) +
             ": only letters, digits, '.', '_' and '-' are allowed";
  }
  if (serial.front() == '.' || serial.front() == '-' || serial.front() == '_')
    return what + " must start with a letter or a digit";
  if (serial.find("..") != std::string_view::npos) return what + " must not contain \"..\"";
  if (auto problem = config_file::StringProblem(serial, config_file::StringKind::kName))
    return what + " is not a valid name: " + *problem;
  return std::nullopt;
}

}  // namespace

std::optional<std::string> SerialProblem(std::string_view serial) {
  return IdProblem(serial, "the serial");
}

std::optional<std::string> OperatorProblem(std::string_view operator_id) {
  return IdProblem(operator_id, "the operator id");
}

}  // namespace hrgbench::app
