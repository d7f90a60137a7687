#include "hrgbench/estimator/split_coriolis_mixing.hpp"

#include <numbers>

namespace hrgbench::estimator {

Xi XiSeenBySlowModel(const Xi& pickoff_xi, const Delta& delta, double frequency_hz) noexcept {
  const double two_omega0 = 4.0 * std::numbers::pi * frequency_hz;  // 2·ω0
  Xi seen = pickoff_xi;
  seen[0] -= delta[4] / two_omega0;
  seen[3] -= delta[5] / two_omega0;
  return seen;
}

Xi PickoffXiFromSlowModel(const Xi& fitted_xi, const Delta& delta, double frequency_hz) noexcept {
  const double two_omega0 = 4.0 * std::numbers::pi * frequency_hz;
  Xi pickoff = fitted_xi;
  pickoff[0] += delta[4] / two_omega0;
  pickoff[3] += delta[5] / two_omega0;
  return pickoff;
}

}  // namespace hrgbench::estimator
