// Data that are all zero (a pick-off not connected, electronics that send nothing but zeros): the
// fit's messages say so in words, never "-nan" (issue 25 row 14).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hrgbench/estimator/maximum_likelihood.hpp"

namespace hrgbench::estimator {
namespace {

std::vector<RunData> ZeroRuns() {
  std::vector<RunData> runs;
  for (int r = 0; r < 3; ++r) {
    RunData run;
    run.id = r + 1;
    run.omega_rad_s = 0.5 * (r + 1) * (r % 2 == 0 ? 1 : -1);
    const int n = 500;
    run.y = Eigen::MatrixXd::Zero(4, n);
    for (int k = 0; k < n; ++k) run.t_s.push_back(k * 2e-3);
    runs.push_back(std::move(run));
  }
  return runs;
}

bool HasNan(const std::string& text) {
  return text.find("nan") != std::string::npos || text.find("NaN") != std::string::npos;
}

TEST(AllZeroData, TheFitSaysSoInWordsNotNan) {
  MlOptions options;
  options.xi_estimated = kNoXi;
  const auto s = EstimateMaximumLikelihood(ZeroRuns(), options);
  std::string messages = s.message + "\n";
  for (const auto& p : s.diagnostics.problems) messages += p + "\n";
  EXPECT_FALSE(HasNan(messages)) << messages;
  EXPECT_NE(s.message.find("run 1: y is all zero"), std::string::npos) << s.Report();
}

}  // namespace
}  // namespace hrgbench::estimator
