#include "app/serial_check.hpp"

#include "hrgbench/config/toml_reader.hpp"

namespace hrgbench::app {
namespace {

bool Allowed(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '_' || c == '-';
}

}  // namespace

std::optional<std::string> SerialProblem(std::string_view serial) {
  if (serial.empty()) return "the serial is empty";
  if (serial.size() > kMaxSerialLength)
    return "the serial is too long: " + std::to_string(serial.size()) + " characters, at most " +
           std::to_string(kMaxSerialLength);
  for (std::size_t i = 0; i < serial.size(); ++i) {
    const auto c = static_cast<unsigned char>(serial[i]);
    if (c < 0x20 || c == 0x7f)
      return "the serial contains a control character (code " + std::to_string(c) +
             ") at position " + std::to_string(i + 1);
    if (!Allowed(serial[i]))
      return std::string("the serial contains '") + (c < 0x80 ? std::string(1, serial[i]) : "?") +
             "' at position " + std::to_string(i + 1) +
             ": only letters, digits, '.', '_' and '-' are allowed";
  }
  if (serial.front() == '.' || serial.front() == '-' || serial.front() == '_')
    return "the serial must start with a letter or a digit";
  if (serial.find("..") != std::string_view::npos) return "the serial must not contain \"..\"";
  if (auto problem = config_file::StringProblem(serial, config_file::StringKind::kName))
    return "the serial is not a valid name: " + *problem;
  return std::nullopt;
}

}  // namespace hrgbench::app
