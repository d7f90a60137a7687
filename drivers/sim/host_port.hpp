#pragma once
// HOST:PORT on the simulators' command lines (hrg-table-sim --tcp, hrg-gyro-sim --table). The port
// is the text after the last ':' and must be all digits in 1..65535 ("1502x" is refused, not read
// as 1502); the host is everything before it and must not be empty.

#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::drivers::sim {

struct HostPort {
  std::string host;
  int port = 0;
};

std::optional<HostPort> ParseHostPort(std::string_view text);

}  // namespace hrgbench::drivers::sim
