#pragma once
// The text of a driver's error message from its parts ("rate ", 2.5, " rad/s is outside ..."): what
// every driver puts in hw::RateTableError::message and hw::GyroError::message. A stream, because
// g++ 12 has no <format> and a message needs readable numbers, not round-trip ones. Not for
// real-time code (allocates).

#include <sstream>
#include <string>

namespace hrgbench::hw {

template <typename... Parts>
std::string ErrorText(const Parts&... parts) {
  std::ostringstream os;
  (os << ... << parts);
  return os.str();
}

}  // namespace hrgbench::hw
