#pragma once
// The reference sessions of ../shared/reference-data (copied to tests/data/reference): written by
// an independent numpy prototype, with that prototype's answers in expected.json.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/run_data.hpp"
#include "hrgbench/session/session.hpp"

namespace hrgbench::testing {

inline std::string ReferenceDir(const std::string& name) {
  return std::string(HRGBENCH_TEST_DATA_DIR) + "/reference/" + name;
}

inline std::vector<estimator::RunData> LoadReferenceRuns(const std::string& name) {
  const auto session = session::ReadSession(ReferenceDir(name));
  EXPECT_TRUE(session.has_value()) << (session ? "" : session.error().ToString());
  return session ? session::ToRunData(*session) : std::vector<estimator::RunData>{};
}

inline const nlohmann::json& Expected() {
  static const nlohmann::json expected = [] {
    std::ifstream in(std::string(HRGBENCH_TEST_DATA_DIR) + "/reference/expected.json");
    return nlohmann::json::parse(in);
  }();
  return expected;
}

inline estimator::Delta DeltaFrom(const nlohmann::json& array) {
  estimator::Delta d;
  for (int j = 0; j < 6; ++j) d[j] = array.at(static_cast<std::size_t>(j)).get<double>();
  return d;
}

inline estimator::Xi XiFrom(const nlohmann::json& array) {
  estimator::Xi xi = estimator::Xi::Zero();
  for (std::size_t k = 0; k < array.size() && k < 4; ++k)
    xi[static_cast<Eigen::Index>(k)] = array.at(k).get<double>();
  return xi;
}

// Truth of a reference session, from its session.json "simulation".
struct ReferenceTruth {
  estimator::Delta delta;
  estimator::Xi xi;
  double sigma = 0.0;
  std::vector<estimator::RunPlan> plans;
};

inline ReferenceTruth LoadReferenceTruth(const std::string& name) {
  std::ifstream in(ReferenceDir(name) + "/session.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  const nlohmann::json& sim = doc.at("simulation");
  ReferenceTruth truth;
  truth.delta = DeltaFrom(sim.at("delta"));
  truth.xi = XiFrom(sim.at("xi"));
  truth.sigma = sim.at("sigma").get<double>();
  for (const nlohmann::json& r : sim.at("runs")) {
    estimator::RunPlan p;
    p.a = r.at("a");
    p.b = r.at("b");
    p.theta_rad = r.at("th");
    p.phi_rad = r.at("ph");
    p.omega_rad_s = r.at("Om");
    p.sample_rate_hz = r.at("fs");
    p.duration_s = r.at("T");
    truth.plans.push_back(p);
  }
  return truth;
}

}  // namespace hrgbench::testing
