#include "hrgbench/config/config_error.hpp"

namespace hrgbench::config_file {

std::string ConfigError::ToString() const {
  std::string text = file.string();
  if (line != 0) text += ":" + std::to_string(line);
  text += ": ";
  if (!key.empty()) {
    text += "key '" + key + "'";
    if (!value.empty()) text += " = " + value;
    text += ": ";
  }
  return text + message;
}

}  // namespace hrgbench::config_file
