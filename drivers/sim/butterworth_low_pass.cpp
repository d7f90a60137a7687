#include "sim/butterworth_low_pass.hpp"

#include <cmath>
#include <numbers>

namespace hrgbench::drivers::sim {

ButterworthLowPass::ButterworthLowPass(int order, double cutoff_hz, double sample_rate_hz)
    : sections_(order / 2) {
  const double pi = std::numbers::pi;
  const double k = std::tan(pi * cutoff_hz / sample_rate_hz);  // pre-warped analog cutoff
  double delay_samples = 0.0;
  for (int i = 0; i < sections_; ++i) {
    // Pole pair i of the analog prototype: Q = 1/(2·sin((2i + 1)·π/(2N))).
    const double q = 1.0 / (2.0 * std::sin((2 * i + 1) * pi / (2.0 * order)));
    const double norm = 1.0 / (1.0 + k / q + k * k);
    Section& s = section_[i];
    s.b0 = k * k * norm;
    s.b1 = 2.0 * s.b0;
    s.b2 = s.b0;
    s.a1 = 2.0 * (k * k - 1.0) * norm;
    s.a2 = (1.0 - k / q + k * k) * norm;
    // Group delay of B(z)/A(z) at DC: Σn·b_n/Σb_n − Σn·a_n/Σa_n (in samples); B's is 1.
    delay_samples += 1.0 - (s.a1 + 2.0 * s.a2) / (1.0 + s.a1 + s.a2);
    state1_[i].setZero();
    state2_[i].setZero();
  }
  group_delay_s_ = delay_samples / sample_rate_hz;
}

void ButterworthLowPass::SetSteadyState(const Eigen::Array4d& input) noexcept {
  // Constant x in, y = x out: s2 = (b2 − a2)·x, s1 = (b1 − a1)·x + s2.
  for (int k = 0; k < sections_; ++k) {
    const Section& s = section_[k];
    state2_[k] = (s.b2 - s.a2) * input;
    state1_[k] = (s.b1 - s.a1) * input + state2_[k];
  }
}

}  // namespace hrgbench::drivers::sim
