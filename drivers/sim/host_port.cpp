#include "sim/host_port.hpp"

#include <charconv>

namespace hrgbench::drivers::sim {

std::optional<HostPort> ParseHostPort(std::string_view text) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos || colon == 0) return std::nullopt;
  const std::string_view digits = text.substr(colon + 1);
  int port = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), port);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() || port < 1 ||
      port > 65535)
    return std::nullopt;
  return HostPort{std::string(text.substr(0, colon)), port};
}

}  // namespace hrgbench::drivers::sim
