#pragma once
// One free run as the estimators see it: time stamps, the four demodulated channels, and the
// angular rate Ω about the sensitive axis during the run (table rate plus the Earth-rate
// component).

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace hrgbench::estimator {

struct RunData {
  int id = 0;                // run number as recorded in the session (1-based), for messages
  double omega_rad_s = 0.0;  // Ω, rad/s
  // How well Ω is known: its standard error, rad/s (the bench records it). NaN or 0: taken as
  // exact.
  double omega_std_rad_s = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> t_s;  // sample times, s, strictly increasing; need not be uniform
  Eigen::Matrix4Xd y;       // y(:, k) = (y1, y2, y3, y4) at t_s[k]

  Eigen::Index size() const { return y.cols(); }
};

// Truth and design of a simulated run.
struct RunPlan {
  double omega_rad_s = 0.0;
  double a = 1.0;  // orbit at release (t = 0), see Orbit in model.hpp
  double b = 0.0;
  double theta_rad = 0.0;
  double phi_rad = 0.0;
  double sample_rate_hz = 100.0;
  double duration_s = 10.0;  // n = round(duration_s·fs) samples at t = k/fs, k = 0 … n−1
};

}  // namespace hrgbench::estimator
