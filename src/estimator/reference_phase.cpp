#include "hrgbench/estimator/reference_phase.hpp"

#include <cmath>

namespace hrgbench::estimator {

bool UndoReferencePhase(Eigen::Ref<Eigen::Matrix4Xd> y,
                        std::span<const double> reference_phase_rad) noexcept {
  if (static_cast<std::size_t>(y.cols()) != reference_phase_rad.size()) return false;
  for (const double chi : reference_phase_rad) {
    if (!std::isfinite(chi)) return false;
  }
  for (Eigen::Index k = 0; k < y.cols(); ++k) {
    const double c = std::cos(reference_phase_rad[static_cast<std::size_t>(k)]);
    const double s = std::sin(reference_phase_rad[static_cast<std::size_t>(k)]);
    for (int channel = 0; channel < 2; ++channel) {
      const double re = y(2 * channel, k), im = y(2 * channel + 1, k);
      y(2 * channel, k) = c * re - s * im;
      y(2 * channel + 1, k) = s * re + c * im;
    }
  }
  return true;
}

}  // namespace hrgbench::estimator
