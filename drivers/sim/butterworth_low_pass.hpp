#pragma once
// ButterworthLowPass: the demodulator's low-pass filter, a Butterworth of even order 2…8 as
// cascaded biquads (bilinear transform with the cutoff pre-warped, so |H| = 1/√2 at cutoff_hz
// exactly), unity gain at DC, run on four streams at once (x1…x4 of the two channels).
//
// Why a real IIR filter and not an ideal one: its group delay and its transient are what a real
// chain has (see drivers/sim/README.md, "What the slow model does not have").
//
// Threads: one thread. Real-time: Filter() is allocation-free and noexcept.

#include <Eigen/Core>
#include <array>

namespace hrgbench::drivers::sim {

class ButterworthLowPass {
 public:
  static constexpr int kMaxOrder = 8;

  // `order` even in [2, 8]; 0 < cutoff_hz < sample_rate_hz/2 (unchecked: CarrierOptions checks).
  ButterworthLowPass(int order, double cutoff_hz, double sample_rate_hz);

  // The state a constant input has settled to (the output equals `input`).
  void SetSteadyState(const Eigen::Array4d& input) noexcept;

  Eigen::Array4d Filter(const Eigen::Array4d& input) noexcept {
    Eigen::Array4d x = input;
    for (int k = 0; k < sections_; ++k) {  // transposed direct form II
      const Section& s = section_[k];
      const Eigen::Array4d y = s.b0 * x + state1_[k];
      state1_[k] = s.b1 * x - s.a1 * y + state2_[k];
      state2_[k] = s.b2 * x - s.a2 * y;
      x = y;
    }
    return x;
  }

  // Group delay at DC, s (the slow signal leaves this much late).
  double group_delay_s() const noexcept { return group_delay_s_; }
  int order() const noexcept { return 2 * sections_; }

 private:
  struct Section {
    double b0, b1, b2, a1, a2;
  };
  int sections_ = 0;
  std::array<Section, kMaxOrder / 2> section_{};
  std::array<Eigen::Array4d, kMaxOrder / 2> state1_{};
  std::array<Eigen::Array4d, kMaxOrder / 2> state2_{};
  double group_delay_s_ = 0.0;
};

}  // namespace hrgbench::drivers::sim
