#include "hrgbench/session/session.hpp"

namespace hrgbench::session {

std::string SessionError::ToString() const {
  std::string out = file.string();
  if (line != 0) {
    out += ':';
    out += std::to_string(line);
  }
  out += ": ";
  if (!field.empty()) {
    out += "field '";
    out += field;
    out += "': ";
  }
  out += message;
  return out;
}

}  // namespace hrgbench::session
