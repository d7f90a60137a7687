#include "app/sim_session.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hrgbench/session/session.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

class SimSessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hrgbench_sim_session_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);

    spec_.file = "bench_configs/sim-unit.toml";
    spec_.serial = "SIM-unit";
    spec_.delta << -0.001, 0.3, 0, 0, 0, 0;
    spec_.xi << 0.01, 0, 0, 0;
    spec_.sigma = 1e-4;
    spec_.seed = 7;
    for (int k = 0; k < 2; ++k) {
      estimator::RunPlan plan;
      plan.omega_rad_s = k == 0 ? -0.1 : 0.1;
      plan.b = 0.1 * k;
      plan.sample_rate_hz = 10.0;
      plan.duration_s = 0.3;
      spec_.runs.push_back(plan);

      estimator::RunData run;
      run.id = k + 1;
      run.omega_rad_s = plan.omega_rad_s;
      run.t_s = {0.0, 0.1, 0.2, 0.3};
      run.y = Eigen::Matrix4Xd::Random(4, 4);
      runs_.push_back(run);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  SimSpec spec_;
  std::vector<estimator::RunData> runs_;
};

TEST_F(SimSessionTest, DocumentCarriesTruthAndProvenance) {
  const session::Session s = MakeSimSession(spec_, runs_, {"v1.2-3-gabc", "deadbeef"});
  EXPECT_EQ(s.serial, "SIM-unit");
  EXPECT_EQ(s.sample_rate_hz, 10.0);
  ASSERT_EQ(s.runs.size(), 2u);
  EXPECT_EQ(s.runs[1].id, 2);
  EXPECT_EQ(s.runs[1].file, "runs/run-002.csv");
  EXPECT_EQ(s.runs[1].omega_rad_s, 0.1);
  const nlohmann::json& doc = s.document;
  EXPECT_EQ(doc["software_version"], "v1.2-3-gabc");
  EXPECT_EQ(doc["spec_sha256"], "deadbeef");
  const nlohmann::json& sim = doc["simulation"];
  for (const char* key : {"delta", "xi", "sigma", "seed", "generator", "runs"}) {
    EXPECT_TRUE(sim.contains(key)) << key;
  }
  EXPECT_EQ(sim["delta"][1].get<double>(), 0.3);
  EXPECT_EQ(sim["seed"].get<std::uint64_t>(), 7u);
  ASSERT_EQ(sim["runs"].size(), 2u);
  for (const char* key :
       {"a", "b", "theta_rad", "phi_rad", "omega_rad_s", "sample_rate_hz", "duration_s"}) {
    EXPECT_TRUE(sim["runs"][1][key].is_number()) << key;
  }
  EXPECT_EQ(sim["runs"][1]["b"].get<double>(), 0.1);
}

TEST_F(SimSessionTest, WritesASessionTheReaderLoadsBack) {
  const session::Session s = MakeSimSession(spec_, runs_, {"v", "sha"});
  auto written = WriteSimSession(dir_, s, runs_, false);
  ASSERT_TRUE(written.has_value()) << written.error();
  auto read = session::ReadSession(dir_);
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  ASSERT_EQ(read->loaded_samples.size(), 2u);
  EXPECT_EQ(read->loaded_samples[1].t_s, runs_[1].t_s);
  EXPECT_EQ(read->loaded_samples[1].y, runs_[1].y);  // %.17g round trip
  EXPECT_EQ(read->document["simulation"]["xi"][0].get<double>(), 0.01);
}

TEST_F(SimSessionTest, RefusesANonEmptyDirectoryWithoutForce) {
  fs::create_directories(dir_);
  std::ofstream(dir_ / "notes.txt") << "keep me";
  const session::Session s = MakeSimSession(spec_, runs_, {"v", "sha"});
  auto refused = WriteSimSession(dir_, s, runs_, false);
  ASSERT_FALSE(refused.has_value());
  EXPECT_NE(refused.error().find("--force"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "session.json"));

  ASSERT_TRUE(WriteSimSession(dir_, s, runs_, true).has_value());
  EXPECT_TRUE(fs::exists(dir_ / "session.json"));
  EXPECT_TRUE(fs::exists(dir_ / "notes.txt"));  // --force replaces a session, nothing else
}

TEST_F(SimSessionTest, ForceRemovesStaleRunFiles) {
  fs::create_directories(dir_ / "runs");
  std::ofstream(dir_ / "runs" / "run-009.csv") << "t_s,y1,y2,y3,y4\n";
  const session::Session s = MakeSimSession(spec_, runs_, {"v", "sha"});
  ASSERT_TRUE(WriteSimSession(dir_, s, runs_, true).has_value());
  EXPECT_FALSE(fs::exists(dir_ / "runs" / "run-009.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "runs" / "run-002.csv"));
}

}  // namespace
}  // namespace hrgbench::app
