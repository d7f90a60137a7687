// The tools end to end: hrg-sim writes the paper's session, hrg-estimate reads it back with each
// method, hrg-design and hrg-compare run on it, and bad input gives exit code 4 (exit_codes.hpp)
// with the culprit named on stderr and nothing on stdout.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "hrgbench/config/sha256.hpp"

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string out;
  std::string err;
};

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Quote(const std::string& s) { return "'" + s + "'"; }

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hrgbench_cli_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);  // keep the evidence of a failure
  }

  // Runs `program args` with stdout and stderr captured in files.
  Result Run(const std::string& program, const std::string& args) {
    const fs::path out = dir_ / "stdout.txt";
    const fs::path err = dir_ / "stderr.txt";
    const std::string command =
        Quote(program) + " " + args + " >" + Quote(out) + " 2>" + Quote(err);
    const int status = std::system(command.c_str());
    Result result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = ReadAll(out);
    result.err = ReadAll(err);
    return result;
  }

  static std::string PaperSpec() {
    return (fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs/sim-paper.toml").string();
  }

  // hrg-sim of the paper's spec into dir_/session.
  fs::path SimulatePaper() {
    const fs::path session = dir_ / "session";
    const Result sim = Run(HRG_SIM, Quote(PaperSpec()) + " -o " + Quote(session));
    EXPECT_EQ(sim.exit_code, 0) << sim.err;
    return session;
  }

  nlohmann::json EstimateJson(const fs::path& session, const std::string& extra) {
    const Result r = Run(HRG_ESTIMATE, Quote(session) + " --json " + extra);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);  // throws (fails the test) unless ONE JSON value
  }

  fs::path dir_;
};

void ExpectRelative(double actual, double expected, double tolerance, const char* what) {
  EXPECT_LE(std::abs(actual - expected), tolerance * std::abs(expected))
      << what << " = " << actual << ", expected " << expected;
}

TEST_F(CliTest, SimThenMaximumLikelihoodRecoversTheTruth) {
  const fs::path session = SimulatePaper();
  const nlohmann::json doc = nlohmann::json::parse(ReadAll(session / "session.json"));
  EXPECT_EQ(doc["spec_sha256"], hrgbench::config_file::Sha256FileHex(PaperSpec()).value());
  EXPECT_TRUE(doc["software_version"].is_string());
  EXPECT_EQ(doc["simulation"]["runs"].size(), 5u);

  const nlohmann::json j = EstimateJson(session, "");
  EXPECT_EQ(j["method"], "ml");
  EXPECT_TRUE(j["converged"].get<bool>()) << j.dump(1);
  ExpectRelative(j["xi"][0].get<double>(), 0.01, 1e-6, "xi1");
  ExpectRelative(j["delta"][1].get<double>(), 0.3, 1e-6, "delta2");
  ASSERT_TRUE(j.contains("truth"));
  EXPECT_EQ(j["truth"]["delta"][1].get<double>(), 0.3);
}

TEST_F(CliTest, PaperMethodReproducesTheNoiseFreeFigure) {
  const fs::path session = SimulatePaper();
  const nlohmann::json j = EstimateJson(session, "--method paper");
  EXPECT_EQ(j["method"], "paper");
  // MODEL.md: the paper's method on exact noise-free data gives δ2* = 0.2985732.
  EXPECT_NEAR(j["delta"][1].get<double>(), 0.2986, 0.001) << j.dump(1);
  for (const auto& s : j["xi_std"]) EXPECT_TRUE(s.is_null());
}

TEST_F(CliTest, PaperXiGridFindsXi1) {
  const fs::path session = SimulatePaper();
  const nlohmann::json j = EstimateJson(session, "--method paper-xi-grid");
  EXPECT_NEAR(j["xi"][0].get<double>(), 0.01, 1e-5) << j.dump(1);
  EXPECT_NEAR(j["delta"][1].get<double>(), 0.30006, 0.001) << j.dump(1);
}

TEST_F(CliTest, ReadableReportByDefault) {
  const fs::path session = SimulatePaper();
  const Result r = Run(HRG_ESTIMATE, Quote(session));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("delta2"), std::string::npos) << r.out;
}

TEST_F(CliTest, MalformedSessionExitsBadInputNamingTheFile) {
  const fs::path session = SimulatePaper();
  nlohmann::json doc = nlohmann::json::parse(ReadAll(session / "session.json"));
  doc["runs"][2]["omega_rad_s"] = "fast";
  std::ofstream(session / "session.json") << doc.dump(1);
  const Result r = Run(HRG_ESTIMATE, Quote(session) + " --json");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("session.json"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST_F(CliTest, MissingRunFileExitsBadInputNamingTheFile) {
  const fs::path session = SimulatePaper();
  fs::remove(session / "runs" / "run-003.csv");
  const Result r = Run(HRG_ESTIMATE, Quote(session) + " --json");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("run-003.csv"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

// hrg-report prints the files it wrote; the page's content is tested in tests/unit/report.
TEST_F(CliTest, ReportWritesThePageAndPrintsItsPath) {
  const fs::path session = SimulatePaper();
  const fs::path page = dir_ / "page.html";
  const Result r =
      Run(HRG_REPORT, Quote(session) + " -o " + Quote(page) + " --no-pdf --no-figures");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, page.string() + "\n");
  EXPECT_NE(ReadAll(page).find("<div id=\"outcome\" data-kind=\"NOT RECORDED\">"),
            std::string::npos);
  // A missing run file is said on the page (and logged), not a failure.
  fs::remove(session / "runs" / "run-003.csv");
  const Result missing = Run(HRG_REPORT, Quote(session) + " --no-pdf --no-figures");
  EXPECT_EQ(missing.exit_code, 0) << missing.err;
  EXPECT_NE(missing.err.find("run-003.csv"), std::string::npos) << missing.err;
  EXPECT_TRUE(fs::exists(session / "report" / "report.html"));
}

// Issue 26: the PDF's sheet is the station's ([report] paper in the session's copy of the station
// file), and --paper overrides it; the page's @page rule is what Chromium prints on.
TEST_F(CliTest, ReportPrintsOnTheStationsPaperUnlessTold) {
  const fs::path session = SimulatePaper();
  const std::string sheet = "@page{size:";
  const auto printed_on = [&](const std::string& args) {
    const Result r = Run(HRG_REPORT, Quote(session) + " --no-pdf --no-figures" + args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const std::string page = ReadAll(session / "report" / "report.html");
    const std::size_t at = page.find(sheet);
    return at == std::string::npos
               ? std::string("(none)")
               : page.substr(at + sheet.size(), page.find(';', at) - at - sheet.size());
  };
  EXPECT_EQ(printed_on(""), "A4");  // no station copy (hrg-sim): A4
  fs::create_directories(session / "config");
  std::ofstream(session / "config" / "station.toml")
      << ReadAll(fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs" / "station-sim.toml")
      << "\n[report]\npaper = \"Letter\"\n";
  EXPECT_EQ(printed_on(""), "letter");
  EXPECT_EQ(printed_on(" --paper a4"), "A4");
}

TEST_F(CliTest, ReportOfAMalformedSessionExitsBadInputNamingFileAndField) {
  const fs::path session = SimulatePaper();
  nlohmann::json doc = nlohmann::json::parse(ReadAll(session / "session.json"));
  doc["runs"][2]["omega_rad_s"] = "fast";
  std::ofstream(session / "session.json") << doc.dump(1);
  const Result r = Run(HRG_REPORT, Quote(session) + " --no-pdf --no-figures");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("session.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("runs[2].omega_rad_s"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_FALSE(fs::exists(session / "report"));
}

TEST_F(CliTest, BadCommandLineExitsBadInput) {
  const Result r = Run(HRG_ESTIMATE, Quote(dir_) + " --method magic");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_TRUE(r.out.empty()) << r.out;
  const Result paper_all = Run(HRG_ESTIMATE, Quote(dir_) + " --method paper --xi all");
  EXPECT_EQ(paper_all.exit_code, 4);
}

TEST_F(CliTest, HelpDocumentsExitCodes) {
  for (const char* tool : {HRG_SIM, HRG_ESTIMATE, HRG_DESIGN, HRG_COMPARE, HRG_REPORT}) {
    const Result r = Run(tool, "--help");
    EXPECT_EQ(r.exit_code, 0) << tool;
    EXPECT_NE(r.out.find("Exit codes"), std::string::npos) << tool << r.out;
  }
}

TEST_F(CliTest, SimRefusesNonEmptyDirectoryWithoutForce) {
  const fs::path session = SimulatePaper();
  const Result again = Run(HRG_SIM, Quote(PaperSpec()) + " -o " + Quote(session));
  EXPECT_EQ(again.exit_code, 4);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  const Result forced = Run(HRG_SIM, Quote(PaperSpec()) + " -o " + Quote(session) + " --force");
  EXPECT_EQ(forced.exit_code, 0) << forced.err;
}

TEST_F(CliTest, SimRejectsABadSpecNamingFileLineKeyValue) {
  const fs::path spec = dir_ / "bad.toml";
  std::string text = ReadAll(PaperSpec());
  const std::string good = "sample_rate_hz = 100.0";
  text.replace(text.find(good), good.size(), "sample_rate_hz = -100.0");
  std::ofstream(spec) << text;
  const Result r = Run(HRG_SIM, Quote(spec) + " -o " + Quote(dir_ / "out"));
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("bad.toml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("defaults.sample_rate_hz"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("-100.0"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "session.json"));
}

// Every run at one Ω: ξ cannot be told from δ3…δ6, so by default ML estimates no ξ and says why.
TEST_F(CliTest, DefaultXiSetFollowsThePlan) {
  const fs::path spec = dir_ / "one-omega.toml";
  std::ofstream(spec) << R"([truth]
delta = [-0.001, 0.3, 0, 0, 0, 0]
xi = [0.01, 0, 0, 0]
[defaults]
a = 1.0
b = 0.1
phi_rad = 0.0
sample_rate_hz = 100.0
duration_s = 10.0
[[runs]]
omega_rad_s = 0.1
theta_rad = 0.0
[[runs]]
omega_rad_s = 0.1
theta_rad = 0.7
)";
  const fs::path session = dir_ / "session";
  ASSERT_EQ(Run(HRG_SIM, Quote(spec) + " -o " + Quote(session)).exit_code, 0);
  const nlohmann::json j = EstimateJson(session, "");
  for (const auto& s : j["xi_std"]) EXPECT_TRUE(s.is_null()) << j.dump(1);
  ASSERT_FALSE(j["warnings"].empty());
  EXPECT_NE(j["warnings"][0].get<std::string>().find("cannot determine"), std::string::npos);

  const Result design = Run(HRG_DESIGN, Quote(spec));
  EXPECT_EQ(design.exit_code, 0) << design.err;
  EXPECT_NE(design.out.find("not identifiable"), std::string::npos) << design.out;
}

TEST_F(CliTest, DesignOfThePapersPlan) {
  const Result r = Run(HRG_DESIGN, Quote(PaperSpec()) + " --sigma 1e-4 --phase-degree 0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  // tests/data/reference/expected.json, crlb_at_sigma_1e-4 of the paper's design (independent
  // prototype, the model's own bound, so --phase-degree 0): δ2 std 0.00429 with ξ known, 0.00678
  // with all ξ unknown.
  EXPECT_NEAR(j["cases"]["xi_known"]["delta_std"][1].get<double>(), 0.004292, 0.0002);
  EXPECT_NEAR(j["cases"]["all_xi_unknown"]["delta_std"][1].get<double>(), 0.006777, 0.0003);
  EXPECT_TRUE(j["cases"]["xi_known"]["xi_std"][0].is_null());

  const Result table = Run(HRG_DESIGN, Quote(PaperSpec()));
  EXPECT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("all xi unknown"), std::string::npos) << table.out;
}

TEST_F(CliTest, CompareRunsAllThreeMethods) {
  const fs::path session = SimulatePaper();
  const Result r = Run(HRG_COMPARE, Quote(session));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* label : {"paper (no xi)", "paper xi1 grid", "ML (all xi)"}) {
    EXPECT_NE(r.out.find(label), std::string::npos) << r.out;
  }
}

}  // namespace
