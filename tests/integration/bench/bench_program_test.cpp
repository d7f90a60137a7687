// The hrg-bench program as an operator (or a crash) meets it: config check, bad configs, an
// unwritable output directory, kill -9 in the middle of a session and `resume`, and Ctrl-C.
// The station is the simulated one, paced at 20× real time so a process can be killed mid-run.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hrgbench/session/session.hpp"

namespace {

namespace fs = std::filesystem;

const std::string kBench = std::string(HRGBENCH_BIN_DIR) + "/hrg-bench";
const fs::path kConfigs = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";

fs::path FreshDir(const std::string& stem) {
  std::random_device rd;
  return fs::temp_directory_path() / ("hrgbench-" + stem + "-" + std::to_string(rd()));
}

struct Output {
  int exit_code = -1;
  std::string out;
};

Output RunBench(const std::string& args) {
  const fs::path log = FreshDir("out");
  const std::string command = kBench + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  Output o;
  o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  o.out = text.str();
  fs::remove(log);
  return o;
}

// station-sim.toml, paced at 20× real time instead of as fast as possible.
fs::path PacedStation(const fs::path& dir) {
  std::ifstream in(kConfigs / "station-sim.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const std::string fast = "faster_than_real_time = true";
  toml.replace(toml.find(fast), fast.size(), "faster_than_real_time = false\ntime_scale = 20.0");
  fs::create_directories(dir);
  const fs::path path = dir / "station-paced.toml";
  std::ofstream(path) << toml;
  return path;
}

// Starts hrg-bench in the background; returns its pid.
pid_t Spawn(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::FILE* out = std::freopen(log.c_str(), "w", stdout);
    (void)out;
    ::dup2(STDOUT_FILENO, STDERR_FILENO);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(kBench.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(kBench.c_str(), argv.data());
    std::_Exit(127);
  }
  return pid;
}

// Waits (wall clock, bounded) until session.json lists at least `n` complete runs.
bool WaitForCompleteRuns(const fs::path& dir, std::size_t n, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    std::ifstream in(dir / "session.json");
    const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
    if (!doc.is_discarded() && doc.contains("runs")) {
      std::size_t complete = 0;
      for (const auto& run : doc["runs"]) complete += run.value("status", "") == "complete";
      if (complete >= n) return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

TEST(BenchProgram, CheckValidatesTheShippedConfigs) {
  const Output o = RunBench("check " + (kConfigs / "station-sim.toml").string() + " " +
                       (kConfigs / "sequence-production.toml").string() + " " +
                       (kConfigs / "limits-example.toml").string());
  EXPECT_EQ(o.exit_code, 0) << o.out;
  EXPECT_NE(o.out.find("ok: station"), std::string::npos) << o.out;
}

TEST(BenchProgram, BadConfigIsAUsageErrorNamingFileLineAndKey) {
  const fs::path dir = FreshDir("badcfg");
  fs::create_directories(dir);
  std::ofstream(dir / "bad.toml") << "[sequence]\nname = \"x\"\nbogus_key = 3\n";
  const Output o = RunBench("check " + (kConfigs / "station-sim.toml").string() + " " +
                       (dir / "bad.toml").string());
  EXPECT_EQ(o.exit_code, 4) << o.out;
  EXPECT_NE(o.out.find("bad.toml"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("bogus_key"), std::string::npos) << o.out;
  fs::remove_all(dir);
}

TEST(BenchProgram, UnwritableOutputIsAnErrorAndMovesNothing) {
  const Output o = RunBench("run --station " + (kConfigs / "station-sim.toml").string() +
                       " --sequence " + (kConfigs / "sequence-paper.toml").string() +
                       " --serial SN-X -o /proc/hrgbench-cannot-write-here");
  EXPECT_EQ(o.exit_code, 2) << o.out;
  EXPECT_NE(o.out.find("/proc/hrgbench-cannot-write-here"), std::string::npos) << o.out;
}

TEST(BenchProgram, KillNineMidRunLeavesAReadableSessionThatResumes) {
  const fs::path work = FreshDir("kill9");
  const fs::path session_dir = work / "session";
  const fs::path station = PacedStation(work);
  const pid_t pid =
      Spawn({"run", "--station", station.string(), "--sequence",
             (kConfigs / "sequence-paper.toml").string(), "--serial", "SN-K9", "-o",
             session_dir.string()},
            work / "run.log");
  ASSERT_GT(pid, 0);
  // Two runs done, the third under way: then the power goes.
  const bool reached = WaitForCompleteRuns(session_dir, 2, std::chrono::seconds(60));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(reached) << "the session did not get through two runs";

  auto crashed = hrgbench::session::ReadSession(session_dir);
  ASSERT_TRUE(crashed) << crashed.error().ToString();
  EXPECT_GE(crashed->loaded_run_ids.size(), 2u);
  EXPECT_EQ(crashed->document.at("state"), "running");  // never closed: the tool can tell

  // A report that cannot be written (a file where its directory goes) is logged and changes
  // neither the outcome nor the exit code.
  std::ofstream(session_dir / "report") << "not a directory\n";
  const Output resumed = RunBench("resume " + session_dir.string() + " --json");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out;
  EXPECT_NE(resumed.out.find("\"report\": null"), std::string::npos) << resumed.out;
  EXPECT_NE(resumed.out.find("session report not written"), std::string::npos) << resumed.out;
  auto done = hrgbench::session::ReadSession(session_dir);
  ASSERT_TRUE(done) << done.error().ToString();
  EXPECT_EQ(done->loaded_run_ids.size(), 5u);
  EXPECT_EQ(done->document.at("state"), "closed");
  EXPECT_EQ(done->document.at("outcome").at("kind"), "PASS");
  EXPECT_TRUE(done->document.contains("resumed_at"));
  fs::remove_all(work);
}

// A serial that could name a folder outside the sessions folder is refused before anything runs
// (the panel's rule, serial_check.hpp), and nothing is written.
TEST(BenchProgram, ASerialThatCouldLeaveTheSessionsFolderIsAUsageError) {
  const fs::path work = FreshDir("serial");
  fs::create_directories(work);
  const pid_t pid = Spawn({"run", "--station", (kConfigs / "station-sim.toml").string(),
                           "--sequence", (kConfigs / "sequence-paper.toml").string(), "--serial",
                           "../escaped", "-o", (work / "session").string()},
                          work / "run.log");
  ASSERT_GT(pid, 0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 4);  // usage
  std::ifstream log(work / "run.log");
  std::stringstream text;
  text << log.rdbuf();
  EXPECT_NE(text.str().find("--serial: "), std::string::npos) << text.str();
  EXPECT_FALSE(fs::exists(work / "session"));
  fs::remove_all(work);
}

// A signal in the middle of run 2: the session stops safely, ABORTED, and the record says who.
void ExpectSignalAborts(int signal, const std::string& reason) {
  const fs::path work = FreshDir("signal" + std::to_string(signal));
  const fs::path session_dir = work / "session";
  const fs::path station = PacedStation(work);
  const pid_t pid =
      Spawn({"run", "--station", station.string(), "--sequence",
             (kConfigs / "sequence-paper.toml").string(), "--serial", "SN-INT", "-o",
             session_dir.string()},
            work / "run.log");
  ASSERT_GT(pid, 0);
  const bool reached = WaitForCompleteRuns(session_dir, 1, std::chrono::seconds(60));
  ::kill(pid, signal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(reached);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3);  // ABORTED
  auto session = hrgbench::session::ReadSession(session_dir);
  ASSERT_TRUE(session) << session.error().ToString();
  EXPECT_GE(session->loaded_run_ids.size(), 1u);
  EXPECT_EQ(session->document.at("outcome").at("kind"), "ABORTED");
  const std::string recorded = session->document.at("outcome").at("reason").get<std::string>();
  EXPECT_EQ(recorded.rfind(reason, 0), 0u) << recorded;
  // Every closed session gets its report, an aborted one too (hrg-report's own tests check it).
  const fs::path report = session_dir / "report" / "report.html";
  EXPECT_TRUE(fs::exists(report));
  std::ifstream page(report);
  std::stringstream html;
  html << page.rdbuf();
  EXPECT_NE(html.str().find("<div id=\"outcome\" data-kind=\"ABORTED\">"), std::string::npos);
  fs::remove_all(work);
}

// Ctrl-C at the terminal, and the panel's Abort (which sends SIGINT to the session's process).
TEST(BenchProgram, CtrlCStopsSafelyAndTheRecordSaysAbortedByOperator) {
  // "... during run 2", "... while the table settled": wherever the signal lands.
  ExpectSignalAborts(SIGINT, "aborted by operator ");
}

// A supervisor (systemd, a shutdown) is not the operator: the record says which signal.
TEST(BenchProgram, SigtermStopsSafelyAndTheRecordSaysSo) {
  ExpectSignalAborts(SIGTERM, "stopped by SIGTERM ");
}

}  // namespace
