#include "count_text.hpp"

#include <cmath>

#include "hrgbench/session/number_text.hpp"

namespace hrgbench::config_file {

std::string CountText(double value) {
  // 2^62: well inside long long, and far above any count a bound lets through.
  constexpr double kLargestWhole = 4611686018427387904.0;
  if (std::isfinite(value) && std::abs(value) < kLargestWhole) {
    return std::to_string(static_cast<long long>(std::round(value)));
  }
  return session::NumberText(value);
}

}  // namespace hrgbench::config_file
