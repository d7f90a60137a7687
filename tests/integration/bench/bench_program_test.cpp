// The hrg-bench program as an operator (or a crash) meets it: config check, bad configs, an
// unwritable output directory, kill -9 in the middle of a session and `resume`, and Ctrl-C.
// The station is the simulated one, paced at 20× real time so a process can be killed mid-run.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"
#include "removed_at_end.hpp"

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

// stdout alone (the logs on stderr are dropped), parsed as one JSON object.
struct JsonOutput {
  int exit_code = -1;
  nlohmann::json doc;
  std::string text;
};

JsonOutput RunBenchJson(const std::string& args) {
  const fs::path log = FreshDir("json");
  const std::string command = kBench + " " + args + " > " + log.string() + " 2>/dev/null";
  const int status = std::system(command.c_str());
  JsonOutput o;
  o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  o.text = text.str();
  o.doc = nlohmann::json::parse(o.text, nullptr, false);
  fs::remove(log);
  return o;
}

// A shipped station (station-sim.toml by default), paced at 20× real time instead of as fast as
// possible, with `extra` appended.
fs::path PacedStation(const fs::path& dir, const std::string& shipped = "station-sim.toml",
                      const std::string& extra = "") {
  std::ifstream in(kConfigs / shipped);
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const std::string fast = "faster_than_real_time = true";
  toml.replace(toml.find(fast), fast.size(), "faster_than_real_time = false\ntime_scale = 20.0");
  fs::create_directories(dir);
  const fs::path path = dir / "station-paced.toml";
  std::ofstream(path) << toml << extra;
  return path;
}

nlohmann::json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in, nullptr, false);
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
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
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path session_dir = work / "session";
  const fs::path station = PacedStation(work);
  const pid_t pid = Spawn({"run", "--station", station.string(), "--sequence",
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

  // The raw CAN log of both processes rebuilds every run, the one the crash cut short included,
  // and the estimate the resumed process made.
  const JsonOutput replay = RunBenchJson("replay " + session_dir.string() + " --json");
  ASSERT_FALSE(replay.doc.is_discarded()) << replay.text;
  EXPECT_EQ(replay.exit_code, 0) << replay.doc.dump(1);
  EXPECT_EQ(replay.doc.at("identical"), true);
  EXPECT_EQ(replay.doc.at("driver").at("host_starts"), 2);
  EXPECT_EQ(replay.doc.at("estimate").at("compared"), true);
  EXPECT_EQ(replay.doc.at("estimate").at("identical"), true);
  std::size_t complete = 0;
  std::size_t earlier_attempts = 0;
  for (const auto& capture : replay.doc.at("captures")) {
    complete += capture.at("status") == "complete" && capture.at("identical") == true;
    earlier_attempts += capture.at("attempt") != "";
  }
  EXPECT_EQ(complete, 5u);
  // The run the kill cut short, when it had been released (else the kill hit between runs).
  EXPECT_LE(earlier_attempts, 1u) << replay.doc.dump(1);
}

// One LSB changed in a sample frame (with its CRC-8 made valid again, as a gateway that rewrote
// it would), a mangled line, a torn end: each is found and named.
std::uint8_t Crc8J1850(std::uint32_t id, const std::uint8_t* data, std::size_t n) {
  // SAE J1850: poly 0x1D, init 0xFF, xor-out 0xFF, over the id (2 bytes, little-endian) then the
  // payload (drivers/gyro_can/README.md).
  std::uint8_t crc = 0xFF;
  const auto feed = [&crc](std::uint8_t byte) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit)
      crc = static_cast<std::uint8_t>((crc & 0x80) != 0 ? (crc << 1) ^ 0x1D : crc << 1);
  };
  feed(static_cast<std::uint8_t>(id & 0xFF));
  feed(static_cast<std::uint8_t>(id >> 8));
  for (std::size_t i = 0; i < n; ++i) feed(data[i]);
  return static_cast<std::uint8_t>(crc ^ 0xFF);
}

std::vector<std::string> Lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

void WriteLines(const fs::path& file, const std::vector<std::string>& lines, bool torn = false) {
  std::ofstream out(file, std::ios::trunc);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    out << lines[i];
    if (!(torn && i + 1 == lines.size())) out << '\n';
  }
}

TEST(BenchProgram, ReplayRebuildsTheRecordFromTheRawCanLogAndFindsWhatWasChanged) {
  const fs::path work = FreshDir("replay");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path session_dir = work / "session";
  fs::create_directories(work);
  const Output ran = RunBench("run --station " + (kConfigs / "station-sim.toml").string() +
                              " --sequence " + (kConfigs / "sequence-paper.toml").string() +
                              " --serial SN-RP -o " + session_dir.string());
  ASSERT_EQ(ran.exit_code, 0) << ran.out;

  const JsonOutput replay = RunBenchJson("replay " + session_dir.string() + " --json");
  ASSERT_FALSE(replay.doc.is_discarded()) << replay.text;
  EXPECT_EQ(replay.exit_code, 0) << replay.doc.dump(1);
  ASSERT_EQ(replay.doc.at("captures").size(), 5u);
  for (const auto& capture : replay.doc.at("captures")) {
    EXPECT_EQ(capture.at("identical"), true) << capture.dump();
    EXPECT_EQ(capture.at("recorded_samples"), 1000);  // 10 s at 100 Hz
  }
  EXPECT_EQ(replay.doc.at("samples_rebuilt"), 5000);
  EXPECT_EQ(replay.doc.at("estimate").at("identical"), true);
  EXPECT_EQ(replay.doc.at("driver").at("host_starts"), 1);
  EXPECT_TRUE(replay.doc.at("log").at("damage").is_null());

  // A run file cut in half (a disk error): the log restores it, byte for byte, into a new
  // session folder that replays identical.
  const fs::path run2 = session_dir / "runs" / "run-002.csv";
  const std::string run2_text = [&] {
    std::ifstream in(run2, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }();
  std::ofstream(run2, std::ios::binary | std::ios::trunc)
      << run2_text.substr(0, run2_text.size() / 2);
  const fs::path rebuilt = work / "rebuilt";
  const Output restoring =
      RunBench("replay " + session_dir.string() + " --rebuild-into " + rebuilt.string());
  EXPECT_EQ(restoring.exit_code, 1) << restoring.out;  // the damaged record is not the log's
  EXPECT_NE(restoring.out.find("run 2 [complete]: DIFFERS: the recorded file cannot be read"),
            std::string::npos)
      << restoring.out;
  std::ifstream restored_file(rebuilt / "runs" / "run-002.csv", std::ios::binary);
  std::stringstream restored;
  restored << restored_file.rdbuf();
  EXPECT_EQ(restored.str(), run2_text);
  EXPECT_EQ(RunBench("replay " + rebuilt.string()).exit_code, 0);
  std::ofstream(run2, std::ios::binary | std::ios::trunc) << run2_text;

  const fs::path log = session_dir / "can" / "session.log";
  const std::vector<std::string> original = Lines(log);
  // The 100th SampleA frame after the first release: y1's low byte + 1, CRC made valid again.
  std::size_t released = 0;
  std::size_t changed = 0;
  std::size_t seen = 0;
  for (std::size_t i = 0; i < original.size() && changed == 0; ++i) {
    if (original[i].find(" 060#") != std::string::npos) released = i;
    if (released == 0 || original[i].find(" 100#") == std::string::npos || ++seen != 100) continue;
    changed = i;
  }
  ASSERT_NE(changed, 0u);
  std::vector<std::string> lines = original;
  {
    std::string& line = lines[changed];
    const std::size_t hash = line.find(" 100#") + 5;
    std::uint8_t data[8];
    for (int b = 0; b < 8; ++b)
      data[b] = static_cast<std::uint8_t>(std::stoi(line.substr(hash + 2 * b, 2), nullptr, 16));
    data[1] = static_cast<std::uint8_t>(data[1] + 1);
    data[7] = Crc8J1850(0x100, data, 7);
    char hex[17];
    for (int b = 0; b < 8; ++b) std::snprintf(hex + 2 * b, 3, "%02X", data[b]);
    line.replace(hash, 16, hex);
  }
  WriteLines(log, lines);
  Output changed_replay = RunBench("replay " + session_dir.string());
  EXPECT_EQ(changed_replay.exit_code, 1) << changed_replay.out;
  EXPECT_NE(changed_replay.out.find("run 1 [complete]: DIFFERS: sample "), std::string::npos)
      << changed_replay.out;
  EXPECT_NE(changed_replay.out.find("y1 recorded "), std::string::npos) << changed_replay.out;
  EXPECT_NE(changed_replay.out.find("does NOT rebuild the record"), std::string::npos);

  // A line mangled in the middle of run 3: read up to it, named, and the runs before it stand.
  lines = original;
  std::size_t releases = 0;
  std::size_t mangled = 0;
  for (std::size_t i = 0; i < lines.size() && mangled == 0; ++i) {
    if (lines[i].find(" 060#") != std::string::npos && ++releases == 3) mangled = i + 50;
  }
  ASSERT_LT(mangled, lines.size());
  lines[mangled] = lines[mangled].substr(0, 20) + "#garbage";
  WriteLines(log, lines);
  const JsonOutput damaged = RunBenchJson("replay " + session_dir.string() + " --json");
  EXPECT_EQ(damaged.exit_code, 1);
  ASSERT_TRUE(damaged.doc.at("log").at("damage").is_string()) << damaged.text;
  const std::string damage = damaged.doc.at("log").at("damage");
  EXPECT_NE(damage.find("line " + std::to_string(mangled + 1) + ": "), std::string::npos) << damage;
  EXPECT_EQ(damaged.doc.at("captures").at(0).at("identical"), true);
  EXPECT_EQ(damaged.doc.at("captures").at(1).at("identical"), true);
  EXPECT_EQ(damaged.doc.at("captures").at(2).at("identical"), false);

  // Torn at the end, as a crash mid-write leaves it.
  lines = original;
  lines.back() = lines.back().substr(0, lines.back().size() / 2);
  WriteLines(log, lines, true);
  const Output torn = RunBench("replay " + session_dir.string());
  EXPECT_EQ(torn.exit_code, 1) << torn.out;
  EXPECT_NE(torn.out.find("line " + std::to_string(lines.size()) + ": cut off"), std::string::npos)
      << torn.out;

  // A run cut short (its record says so) whose log lost the end of it, as a kill -9 can leave
  // them (the run file and the log are written out independently): the common beginning is
  // compared, and identical.
  lines = original;
  std::size_t fifth = 0;
  releases = 0;
  for (std::size_t i = 0; i < lines.size() && fifth == 0; ++i) {
    if (lines[i].find(" 060#") != std::string::npos && ++releases == 5) fifth = i;
  }
  ASSERT_NE(fifth, 0u);
  lines.resize(fifth + 600);  // about 300 of run 5's 1000 samples
  WriteLines(log, lines);
  const fs::path record = session_dir / "session.json";
  const std::string record_text = [&] {
    std::ifstream in(record);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }();
  nlohmann::json doc = nlohmann::json::parse(record_text);
  doc.at("runs").at(4).at("status") = "aborted";
  std::ofstream(record, std::ios::trunc) << doc.dump(2);
  const JsonOutput cut = RunBenchJson("replay " + session_dir.string() + " --json --no-estimate");
  EXPECT_EQ(cut.exit_code, 0) << cut.text;
  const nlohmann::json& fifth_capture = cut.doc.at("captures").at(4);
  EXPECT_EQ(fifth_capture.at("identical"), true) << fifth_capture.dump();
  EXPECT_EQ(fifth_capture.at("recorded_samples"), 1000);
  EXPECT_LT(fifth_capture.at("rebuilt_samples").get<int>(), 1000);
  EXPECT_NE(fifth_capture.at("note").get<std::string>().find("the log kept the first"),
            std::string::npos)
      << fifth_capture.dump();
  std::ofstream(record, std::ios::trunc) << record_text;

  // The record says its log speaks gyro CAN protocol v2 as node 0. A log recorded before v2 (no
  // can_log.protocol: v1's fixed identifiers) is refused by name, not misread.
  nlohmann::json v1 = nlohmann::json::parse(record_text);
  EXPECT_EQ(v1.at("can_log").at("protocol"), 2);
  EXPECT_EQ(v1.at("can_log").at("node"), 0);
  v1.at("can_log").erase("protocol");
  std::ofstream(record, std::ios::trunc) << v1.dump(2);
  const Output old_log = RunBench("replay " + session_dir.string());
  EXPECT_NE(old_log.exit_code, 0) << old_log.out;
  EXPECT_NE(old_log.out.find("field 'can_log.protocol': absent (version 1): the log speaks gyro "
                             "CAN protocol v1 and this hrg-bench replays v2 only"),
            std::string::npos)
      << old_log.out;
  std::ofstream(record, std::ios::trunc) << record_text;

  // Not a session: a usage error naming the file.
  const Output absent = RunBench("replay " + (work / "absent").string());
  EXPECT_EQ(absent.exit_code, 4) << absent.out;
  EXPECT_NE(absent.out.find("session.json"), std::string::npos) << absent.out;
}

// A serial that could name a folder outside the sessions folder is refused before anything runs
// (the panel's rule, serial_check.hpp), and nothing is written.
TEST(BenchProgram, ASerialThatCouldLeaveTheSessionsFolderIsAUsageError) {
  const fs::path work = FreshDir("serial");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
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
}

// A signal in the middle of run 2: the session stops safely, ABORTED, and the record says who.
void ExpectSignalAborts(int signal, const std::string& reason) {
  const fs::path work = FreshDir("signal" + std::to_string(signal));
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path session_dir = work / "session";
  const fs::path station = PacedStation(work);
  const pid_t pid = Spawn({"run", "--station", station.string(), "--sequence",
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

// A fixture of four units (station-sim-fixture.toml): killed after two runs, resumed; every unit
// ends with all its runs and its verdict, and fixture.json ties the four together.
TEST(BenchProgram, FixtureKilledMidRunResumesEveryUnit) {
  const fs::path work = FreshDir("fixture-kill9");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path fixture = work / "fixture";
  const fs::path station = PacedStation(work, "station-sim-fixture.toml");
  const pid_t pid =
      Spawn({"run", "--station", station.string(), "--sequence",
             (kConfigs / "sequence-paper.toml").string(), "--serial", "FX-1", "--serial", "FX-2",
             "--serial", "FX-3", "--serial", "FX-4", "-o", fixture.string()},
            work / "run.log");
  ASSERT_GT(pid, 0);
  const bool reached = WaitForCompleteRuns(fixture / "D-FX-4", 2, std::chrono::seconds(90));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(reached) << ReadText(work / "run.log");
  // The fixture's record was written before the first run: which unit sits where.
  const nlohmann::json before = ReadJson(fixture / "fixture.json");
  ASSERT_FALSE(before.is_discarded());
  ASSERT_EQ(before.at("units").size(), 4u);
  EXPECT_EQ(before.at("units").at(2).at("position"), "C");
  EXPECT_EQ(before.at("units").at(2).at("serial"), "FX-3");
  EXPECT_EQ(before.at("units").at(2).at("folder"), "C-FX-3");
  EXPECT_TRUE(before.at("units").at(2).at("outcome").is_null());
  // C and D share one bus as nodes 1 and 2 (station-sim-fixture.toml).
  EXPECT_EQ(before.at("units").at(2).at("can_interface"), "vsim-CD");
  EXPECT_EQ(before.at("units").at(2).at("can_node"), 1);
  EXPECT_EQ(before.at("units").at(3).at("can_interface"), "vsim-CD");
  EXPECT_EQ(before.at("units").at(3).at("can_node"), 2);

  const JsonOutput resumed = RunBenchJson("resume " + fixture.string() + " --json");
  ASSERT_FALSE(resumed.doc.is_discarded()) << resumed.text;
  EXPECT_EQ(resumed.exit_code, 0) << resumed.doc.dump(1);
  EXPECT_EQ(resumed.doc.at("fixture"), fixture.string());
  const nlohmann::json after = ReadJson(fixture / "fixture.json");
  EXPECT_EQ(after.at("started"), before.at("started"));
  const std::vector<std::string> folders{"A-FX-1", "B-FX-2", "C-FX-3", "D-FX-4"};
  for (std::size_t u = 0; u < 4; ++u) {
    SCOPED_TRACE(folders[u]);
    EXPECT_EQ(resumed.doc.at("units").at(u).at("outcome"), "PASS");
    EXPECT_EQ(after.at("units").at(u).at("outcome").at("kind"), "PASS");
    auto done = hrgbench::session::ReadSession(fixture / folders[u]);
    ASSERT_TRUE(done) << done.error().ToString();
    EXPECT_EQ(done->loaded_run_ids.size(), 5u);
    EXPECT_TRUE(done->document.contains("resumed_at"));
    EXPECT_EQ(done->document.at("fixture").at("position"), std::string(1, "ABCD"[u]));
    EXPECT_EQ(done->document.at("fixture").at("units").size(), 4u);
  }
  // Each unit's raw CAN log rebuilds its record, across both processes.
  const JsonOutput replay = RunBenchJson("replay " + fixture.string() + " --json");
  EXPECT_EQ(replay.exit_code, 0) << replay.text;
  ASSERT_FALSE(replay.doc.is_discarded()) << replay.text;
  EXPECT_EQ(replay.doc.at("identical"), true);
  ASSERT_EQ(replay.doc.at("units").size(), 4u);
  for (const auto& unit : replay.doc.at("units")) {
    EXPECT_EQ(unit.at("identical"), true) << unit.dump(1);
    EXPECT_EQ(unit.at("driver").at("host_starts"), 2) << unit.at("position");
  }
  const JsonOutput one = RunBenchJson("replay " + fixture.string() + " --unit FX-3 --json");
  EXPECT_EQ(one.exit_code, 0) << one.text;
  ASSERT_EQ(one.doc.at("units").size(), 1u);
  EXPECT_EQ(one.doc.at("units").at(0).at("position"), "C");
  EXPECT_EQ(RunBench("replay " + fixture.string() + " --unit Z").exit_code, 4);
}

// A unit that never gets ready ends as ERROR; the others PASS; the fixture's exit code is the
// worst unit's. A resume continues that unit only: the others' records are not touched.
TEST(BenchProgram, FixtureResumeContinuesOnlyTheUnitsWithoutAVerdict) {
  const fs::path work = FreshDir("fixture-resume");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path fixture = work / "fixture";
  fs::create_directories(work);
  std::string toml = ReadText(kConfigs / "station-sim-fixture.toml");
  const std::string b = "position = \"B\"\n";
  toml.replace(toml.find(b), b.size(),
               b + "[fixture.faults]\ngyro_never_ready = true\n[[fixture]]\n" +
                   "position = \"B2\"\nfitted = false\n");
  std::ofstream(work / "station.toml") << toml;
  // The paper's sequence with a short warm-up window (the units are at rest at 25 °C).
  std::string sequence = ReadText(kConfigs / "sequence-paper.toml");
  const std::string window = "window_s = 60.0";
  sequence.replace(sequence.find(window), window.size(), "window_s = 1.0");
  std::ofstream(work / "sequence.toml") << sequence;
  const JsonOutput first = RunBenchJson(
      "run --station " + (work / "station.toml").string() + " --sequence " +
      (work / "sequence.toml").string() +
      " --serial A=U1 --serial C=U3 --serial B=U2 --serial D=U4 --json -o " + fixture.string());
  ASSERT_FALSE(first.doc.is_discarded()) << first.text;
  EXPECT_EQ(first.exit_code, 2) << first.doc.dump(1);
  const std::vector<std::string> expected{"PASS", "ERROR", "PASS", "PASS"};
  for (std::size_t u = 0; u < 4; ++u)
    EXPECT_EQ(first.doc.at("units").at(u).at("outcome"), expected[u]) << first.doc.dump(1);
  EXPECT_EQ(first.doc.at("units").at(1).at("serial"), "U2");
  const std::string passed = ReadText(fixture / "A-U1" / "session.json");

  const JsonOutput again = RunBenchJson("resume " + fixture.string() + " --json");
  ASSERT_FALSE(again.doc.is_discarded()) << again.text;
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_EQ(ReadText(fixture / "A-U1" / "session.json"), passed);  // not touched
  EXPECT_NE(again.doc.at("units").at(0).at("reason").get<std::string>().find("kept from before"),
            std::string::npos);
  const nlohmann::json b_doc = ReadJson(fixture / "B-U2" / "session.json");
  EXPECT_TRUE(b_doc.contains("resumed_at"));
  EXPECT_EQ(b_doc.at("outcome").at("kind"), "ERROR");
}

// hrg-bench with `env` ("NAME=value ...") in its environment; stdout and stderr together. A
// process killed by a kill point exits through the shell as 128 + SIGKILL.
Output RunBenchWith(const std::string& env, const std::string& args) {
  const fs::path log = FreshDir("out");
  const std::string command = env + " " + kBench + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  Output o;
  o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  o.out = ReadText(log);
  fs::remove(log);
  return o;
}
constexpr int kKilled = 128 + SIGKILL;

// Every finished run file under `dir` (any depth) with its bytes: what a resume must not change.
std::map<std::string, std::string> FinishedRuns(const fs::path& dir) {
  std::map<std::string, std::string> runs;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec);
       it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    if (name.size() > 4 && name.rfind("run-", 0) == 0 && name.ends_with(".csv"))
      runs[fs::relative(it->path(), dir).string()] = ReadText(it->path());
  }
  return runs;
}

// The paper's sequence with a short warm-up window and two runs of 1 s: a fixture runs in
// seconds (its fit is poor; these tests look at the record, not the verdict).
fs::path ShortSequence(const fs::path& work) {
  std::string sequence = ReadText(kConfigs / "sequence-paper.toml");
  const std::string window = "window_s = 60.0";
  sequence.replace(sequence.find(window), window.size(), "window_s = 1.0");
  const std::string length = "free_run_s = 10.0";
  sequence.replace(sequence.find(length), length.size(), "free_run_s = 1.0");
  // Keep runs 1 and 2: cut from the third [[runs]] on.
  std::size_t at = 0;
  for (int k = 0; k < 3; ++k) at = sequence.find("[[runs]]", at + 1);
  if (at != std::string::npos) sequence.resize(at);
  const fs::path path = work / "sequence-short.toml";
  std::ofstream(path) << sequence;
  return path;
}

// A shipped station without its results store (nothing uploaded, session.json untouched by a mark).
fs::path StationWithoutStore(const fs::path& work, const std::string& shipped) {
  std::string toml = ReadText(kConfigs / shipped);
  const std::string store = "[results]\nurl = \"sqlite://../build/out/results.sqlite\"\n";
  const std::size_t at = toml.find(store);
  if (at != std::string::npos) toml.erase(at, store.size());
  const fs::path path = work / ("nostore-" + shipped);
  std::ofstream(path) << toml;
  return path;
}

// No Chromium: the PDF is refused at once (a warning), which keeps each session to seconds.
const std::string kNoPdf = "HRGBENCH_CHROMIUM=/bin/false";

// Row 5 of issue 25: a fixture killed at any write before its first run (every kill point, found
// by name from an uninterrupted run, not by a sleep) and at some later ones leaves a folder that
// `resume` completes, with every run finished before the kill unchanged; a folder killed before
// its record existed is refused with the reason and what to do.
TEST(BenchProgram, FixtureKilledAtAnyWritePointResumes) {
  const fs::path work = FreshDir("fixture-kill-points");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  fs::create_directories(work);
  const fs::path sequence = ShortSequence(work);
  const std::string run = "run --station " +
                          StationWithoutStore(work, "station-sim-fixture.toml").string() +
                          " --sequence " + sequence.string() +
                          " --serial KP1 --serial KP2 --serial KP3 --serial KP4 -o ";
  const fs::path points_log = work / "points.log";
  const Output whole = RunBenchWith(kNoPdf + " HRGBENCH_TEST_KILL_LOG=" + points_log.string(),
                                    run + (work / "ref").string());
  ASSERT_EQ(whole.exit_code, 0) << whole.out;
  std::vector<std::string> points;
  {
    std::ifstream in(points_log);
    for (std::string line; std::getline(in, line);) points.push_back(line);
  }
  const auto first_run = std::find(points.begin(), points.end(), "run.begin");
  ASSERT_NE(first_run, points.end());
  // Every point up to the first run's start, then every later run.end and the report.
  std::vector<std::size_t> chosen;
  for (std::size_t k = 1; k <= static_cast<std::size_t>(first_run - points.begin()) + 1; ++k)
    chosen.push_back(k);
  for (std::size_t k = chosen.size() + 1; k <= points.size(); ++k)
    if (points[k - 1] == "run.end" || points[k - 1] == "report") chosen.push_back(k);
  int not_started = 0;
  for (const std::size_t k : chosen) {
    SCOPED_TRACE("killed at #" + std::to_string(k) + " (" + points[k - 1] + ")");
    const fs::path fixture = work / ("k" + std::to_string(k));
    const Output killed = RunBenchWith(kNoPdf + " HRGBENCH_TEST_KILL_AT=#" + std::to_string(k),
                                       run + fixture.string());
    ASSERT_EQ(killed.exit_code, kKilled) << killed.out;
    const std::map<std::string, std::string> before = FinishedRuns(fixture);
    const Output resumed = RunBenchWith(kNoPdf, "resume " + fixture.string());
    if (!fs::exists(fixture / "fixture.json")) {
      // Killed before the record: nothing ran, and the refusal says so and what to do.
      ++not_started;
      EXPECT_EQ(resumed.exit_code, 4) << resumed.out;
      EXPECT_NE(resumed.out.find("nothing was run"), std::string::npos) << resumed.out;
      EXPECT_NE(resumed.out.find("start the session again"), std::string::npos) << resumed.out;
      continue;
    }
    // Resumed to the end: a verdict of the fit (the 1 s runs may not PASS), never a refusal.
    ASSERT_TRUE(resumed.exit_code >= 0 && resumed.exit_code <= 2) << resumed.out;
    const nlohmann::json record = ReadJson(fixture / "fixture.json");
    for (const auto& unit : record.at("units")) {
      EXPECT_TRUE(unit.at("outcome").is_object()) << unit.dump();
      const fs::path unit_record = fixture / unit.at("folder").get<std::string>() / "session.json";
      ASSERT_TRUE(fs::exists(unit_record)) << unit_record << "\n" << resumed.out;
      const nlohmann::json session = ReadJson(unit_record);
      EXPECT_EQ(session.at("state"), "closed") << unit.at("folder");
      for (const auto& r : session.at("runs")) EXPECT_EQ(r.at("status"), "complete") << r.dump();
      EXPECT_TRUE(
          fs::exists(fixture / unit.at("folder").get<std::string>() / "report" / "report.html"))
          << unit.at("folder");
    }
    const std::map<std::string, std::string> after = FinishedRuns(fixture);
    for (const auto& [file, bytes] : before) {
      ASSERT_TRUE(after.contains(file)) << file;
      EXPECT_TRUE(after.at(file) == bytes) << file << " changed by the resume";
    }
    EXPECT_EQ(after.size(), 4u * 2u);
    fs::remove_all(fixture);
  }
  // Only the points before fixture.json is in place: the config copies and fixture.json's own
  // temporary.
  EXPECT_LE(not_started, 5);
}

// Row 6 of issue 25: a session closed as PASS and killed during its report is final: `resume`
// writes the missing report and leaves session.json byte for byte as it was.
TEST(BenchProgram, ResumeOfAClosedRecordFinishesTheReportAndRewritesNothing) {
  const fs::path work = FreshDir("closed-resume");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  fs::create_directories(work);
  const fs::path session_dir = work / "session";
  const Output killed = RunBenchWith(
      kNoPdf + " HRGBENCH_TEST_KILL_AT=report",
      "run --station " + StationWithoutStore(work, "station-sim.toml").string() + " --sequence " +
          ShortSequence(work).string() + " --serial SN-CL -o " + session_dir.string());
  ASSERT_EQ(killed.exit_code, kKilled) << killed.out;
  const nlohmann::json closed = ReadJson(session_dir / "session.json");
  ASSERT_EQ(closed.at("state"), "closed");
  const std::string kind = closed.at("outcome").value("kind", std::string());
  ASSERT_TRUE(kind == "PASS" || kind == "FAIL") << closed.at("outcome").dump();
  ASSERT_FALSE(fs::exists(session_dir / "report" / "report.html"));
  // The operator read the outcome before the report began (issue 26 §4: the PDF is off the
  // critical path): it was printed when the kill came.
  EXPECT_NE(killed.out.find(kind + ": "), std::string::npos) << killed.out;
  EXPECT_NE(killed.out.find("session: " + session_dir.string()), std::string::npos) << killed.out;
  const std::string record = ReadText(session_dir / "session.json");

  ::setenv("HRGBENCH_CHROMIUM", "/bin/false", 1);  // as kNoPdf, for RunBenchJson
  const JsonOutput resumed = RunBenchJson("resume " + session_dir.string() + " --json");
  ::unsetenv("HRGBENCH_CHROMIUM");
  ASSERT_FALSE(resumed.doc.is_discarded()) << resumed.text;
  EXPECT_EQ(resumed.doc.at("outcome"), kind);
  EXPECT_TRUE(ReadText(session_dir / "session.json") == record)
      << "the closed record was rewritten:\n"
      << ReadText(session_dir / "session.json");
  EXPECT_TRUE(fs::exists(session_dir / "report" / "report.html"));
  // Again: nothing left to do, nothing changes.
  RunBenchWith(kNoPdf, "resume " + session_dir.string());
  EXPECT_TRUE(ReadText(session_dir / "session.json") == record);
}

// Whether process `pid` has ended (gone, or a zombie nobody has reaped yet).
bool ProcessEnded(pid_t pid) {
  if (::kill(pid, 0) != 0) return true;
  const std::string stat = ReadText("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t paren = stat.rfind(')');
  return paren == std::string::npos || stat.substr(paren + 2, 1) == "Z";
}

// Row 11 of issue 25: a kill -9 while the report's Chromium runs takes Chromium with it
// (PR_SET_PDEATHSIG), and the next report removes the temporary folders the killed one left.
TEST(BenchProgram, AKilledReportLeavesNoChildAndTheNextReportRemovesItsTemporaryFolders) {
  const fs::path work = FreshDir("report-kill");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path tmp = work / "tmp";
  fs::create_directories(tmp);
  // A "Chromium" that says who it is and then runs until it is killed.
  const fs::path chromium = work / "chromium.sh";
  std::ofstream(chromium) << "#!/bin/sh\necho $$ > " << (work / "child.pid").string()
                          << ".tmp && mv " << (work / "child.pid").string() << ".tmp "
                          << (work / "child.pid").string() << "\nexec sleep 300\n";
  fs::permissions(chromium, fs::perms::owner_all);
  const std::string run = "run --station " +
                          StationWithoutStore(work, "station-sim.toml").string() + " --sequence " +
                          ShortSequence(work).string() + " --serial SN-RK -o ";
  ::setenv("TMPDIR", tmp.c_str(), 1);
  ::setenv("HRGBENCH_CHROMIUM", chromium.c_str(), 1);
  std::vector<std::string> args;
  std::istringstream words(run + (work / "s1").string());
  for (std::string w; words >> w;) args.push_back(w);
  const pid_t bench = Spawn(args, work / "run.log");
  ::unsetenv("HRGBENCH_CHROMIUM");
  ::unsetenv("TMPDIR");
  ASSERT_GT(bench, 0);
  // Hang guard only: the session takes seconds.
  for (int i = 0; i < 1200 && !fs::exists(work / "child.pid"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(fs::exists(work / "child.pid")) << ReadText(work / "run.log");
  const pid_t child = std::stoi(ReadText(work / "child.pid"));
  ::kill(bench, SIGKILL);
  int status = 0;
  ::waitpid(bench, &status, 0);
  bool ended = false;
  for (int i = 0; i < 200 && !(ended = ProcessEnded(child)); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (!ended) ::kill(child, SIGKILL);
  EXPECT_TRUE(ended) << "the report's child " << child << " outlived hrg-bench's kill -9";
  const std::string mark = "-" + std::to_string(bench) + "-";
  const auto stale = [&] {
    int n = 0;
    for (const auto& entry : fs::directory_iterator(tmp))
      n += entry.path().filename().string().find(mark) != std::string::npos;
    return n;
  };
  EXPECT_GE(stale(), 1);  // the killed report's Chromium profile
  const Output next =
      RunBenchWith("TMPDIR=" + tmp.string() + " " + kNoPdf, run + (work / "s2").string());
  EXPECT_LE(next.exit_code, 2) << next.out;
  EXPECT_EQ(stale(), 0) << "the next report left the killed one's temporary folders";
}

// Row 6 of issue 25: a disk that fills mid-session. The session runs on a tmpfs just larger than
// the recorder's reserve (mounted in a user namespace: no root; skipped where the kernel refuses
// one); the disk fills while it records, and the reserve given back lets session.json say why it
// ended instead of staying "running".
TEST(BenchProgram, ADiskThatFillsMidSessionLeavesTheReasonInTheRecord) {
  if (std::system("unshare -rm true > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "no user namespaces here (unshare -rm)";
  const fs::path work = FreshDir("disk-full");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path mount = work / "mnt";
  fs::create_directories(mount);
  const std::string run = kBench + " run --station " +
                          StationWithoutStore(work, "station-sim.toml").string() + " --sequence " +
                          ShortSequence(work).string() + " --serial SN-DF --events " +
                          (work / "events.jsonl").string() + " -o " + (mount / "s").string();
  // 512 KiB of reserve and 48 KiB for the record: the runs and the CAN log do not fit.
  const std::string script = "mount -t tmpfs -o size=560k none " + mount.string() + " && " +
                             kNoPdf + " " + run + " > " + (work / "run.log").string() +
                             " 2>&1; cp -a " + (mount / "s").string() + " " + (work / "s").string();
  const std::string command = "unshare -rm sh -c '" + script + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << ReadText(work / "run.log");
  const nlohmann::json record = ReadJson(work / "s" / "session.json");
  ASSERT_FALSE(record.is_discarded()) << ReadText(work / "run.log");
  EXPECT_EQ(record.at("state"), "closed") << ReadText(work / "run.log");
  ASSERT_TRUE(record.contains("outcome")) << record.dump(1);
  EXPECT_EQ(record.at("outcome").at("kind"), "ERROR");
  EXPECT_NE(record.at("outcome").at("reason").get<std::string>().find("No space left"),
            std::string::npos)
      << record.at("outcome").dump(1);
  // A second program (the panel) learns it from the event stream, which lives elsewhere.
  nlohmann::json outcome;
  for (const std::string& line : Lines(work / "events.jsonl")) {
    const nlohmann::json event = nlohmann::json::parse(line, nullptr, false);
    if (!event.is_discarded() && event.value("type", "") == "outcome") outcome = event;
  }
  ASSERT_FALSE(outcome.is_null()) << ReadText(work / "events.jsonl");
  EXPECT_EQ(outcome.at("outcome"), "ERROR") << outcome.dump(1);
  EXPECT_NE(outcome.at("reason").get<std::string>().find("No space left"), std::string::npos)
      << outcome.dump(1);
}

// A folder that holds no record is refused with the reason and what to do.
TEST(BenchProgram, ResumeOfAFolderWithoutARecordSaysNothingRan) {
  const fs::path work = FreshDir("no-record");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  fs::create_directories(work / "config");
  const Output resumed = RunBench("resume " + work.string());
  EXPECT_EQ(resumed.exit_code, 4);
  EXPECT_NE(resumed.out.find("neither session.json nor fixture.json"), std::string::npos)
      << resumed.out;
  EXPECT_NE(resumed.out.find("nothing was run"), std::string::npos) << resumed.out;
}

// Issue 28's one command: a unit that passes is tuned at once (its compensation written over CAN,
// refined and verified on the table), tune.json beside its record; `tune` refuses a folder that
// is not a PASS session before anything moves.
TEST(BenchProgram, RunWithTuneTunesAPassingUnitAndTuneRefusesWhatIsNotAPass) {
  const fs::path work = FreshDir("tune");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path dir = work / "unit";
  const Output run =
      RunBench("run --station " + (kConfigs / "station-sim.toml").string() + " --sequence " +
               (kConfigs / "sequence-production.toml").string() + " --limits " +
               (kConfigs / "limits-example.toml").string() +
               " --serial TUNE-1 --prompts confirm --report none --tune -o " + dir.string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_NE(run.out.find("tune PASS"), std::string::npos) << run.out;
  const nlohmann::json tune = ReadJson(dir / "tune.json");
  ASSERT_FALSE(tune.is_discarded());
  EXPECT_EQ(tune.at("format"), "hrgbench-tune");
  EXPECT_EQ(tune.at("ok"), true) << tune.at("why");
  EXPECT_EQ(tune.at("block_at_end"), "refined");
  // limits-example.toml's [tune]: the rate error at both rates, the bias and the scale factor,
  // each judged with its guard band and met.
  EXPECT_EQ(tune.at("verdict").at("outcome"), "PASS") << tune.at("verdict").dump();
  ASSERT_EQ(tune.at("verdict").at("checks").size(), 4u);
  for (const nlohmann::json& check : tune.at("verdict").at("checks"))
    EXPECT_EQ(check.at("status"), "PASS") << check.at("message");
  ASSERT_EQ(tune.at("verification").at("rates").size(), 2u);
  for (const nlohmann::json& rate : tune.at("verification").at("rates")) {
    EXPECT_EQ(rate.at("met"), true);
    EXPECT_LT(rate.at("after_rms_rad_s").get<double>(),
              rate.at("before_rms_rad_s").get<double>() / 100.0);
  }
  // The session's own record is untouched by the tuning: still a PASS.
  EXPECT_EQ(ReadJson(dir / "session.json").at("outcome").at("kind"), "PASS");

  fs::create_directories(work / "empty");
  const Output refused = RunBench("tune " + (work / "empty").string());
  EXPECT_EQ(refused.exit_code, 4) << refused.out;
  const Output one_sign = RunBench("tune " + dir.string() + " --rates 0.3 1.0");
  EXPECT_EQ(one_sign.exit_code, 4) << one_sign.out;
  EXPECT_NE(one_sign.out.find("both signs"), std::string::npos) << one_sign.out;
}

TEST(BenchProgram, FixtureSerialsMustMatchItsPositions) {
  const std::string run = "run --station " + (kConfigs / "station-sim-fixture.toml").string() +
                          " --sequence " + (kConfigs / "sequence-paper.toml").string();
  const Output three = RunBench(run + " --serial S1 --serial S2 --serial S3 -o /tmp/never");
  EXPECT_EQ(three.exit_code, 4);
  EXPECT_NE(three.out.find("3 serial(s) for 4 fitted position(s) (A, B, C, D)"), std::string::npos)
      << three.out;
  const Output unknown =
      RunBench(run + " --serial A=S1 --serial B=S2 --serial C=S3 --serial E=S4 -o /tmp/never");
  EXPECT_EQ(unknown.exit_code, 4);
  EXPECT_NE(unknown.out.find("no fitted position 'E'"), std::string::npos) << unknown.out;
  const Output twice =
      RunBench(run + " --serial S1 --serial S1 --serial S3 --serial S4 -o /tmp/never");
  EXPECT_EQ(twice.exit_code, 4);
  EXPECT_NE(twice.out.find("the same unit in two positions"), std::string::npos) << twice.out;
  EXPECT_FALSE(fs::exists("/tmp/never"));
  const Output check = RunBench("check " + (kConfigs / "station-sim-fixture.toml").string() + " " +
                                (kConfigs / "sequence-production.toml").string());
  EXPECT_EQ(check.exit_code, 0) << check.out;
  EXPECT_NE(check.out.find("vsim-CD (2 units: C, D) at 1000 kbit/s, at most 59.7 % busy"),
            std::string::npos)
      << check.out;
  EXPECT_NE(check.out.find("  vsim-A: A, at most 29.8 % busy\n"), std::string::npos) << check.out;
  EXPECT_NE(check.out.find("  vsim-CD: C, D, at most 59.7 % busy\n"), std::string::npos)
      << check.out;
}

}  // namespace

// Issue 26 §1: the operator is recorded: `run --operator` in a unit's record and in every unit of
// a fixture's, read back through the typed record; `resume --operator` in the resume's entry,
// the start's operator kept; a bad id refused before anything runs.
TEST(BenchProgram, TheOperatorIsRecordedByRunFixtureAndResume) {
  const fs::path work = FreshDir("operator");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  fs::create_directories(work);
  const fs::path sequence = ShortSequence(work);
  const fs::path one = work / "one";
  const Output single = RunBenchWith(
      kNoPdf, "run --station " + StationWithoutStore(work, "station-sim.toml").string() +
                  " --sequence " + sequence.string() + " --serial SN-OP --operator OP-17 -o " +
                  one.string());
  ASSERT_TRUE(single.exit_code >= 0 && single.exit_code <= 2) << single.out;
  EXPECT_EQ(ReadJson(one / "session.json").at("operator"), "OP-17");
  const auto typed = hrgbench::session::ReadSessionRecord(one);
  ASSERT_TRUE(typed);
  EXPECT_EQ(typed->operator_name, "OP-17");

  const fs::path fixture = work / "fixture";
  const Output four = RunBenchWith(
      kNoPdf, "run --station " + StationWithoutStore(work, "station-sim-fixture.toml").string() +
                  " --sequence " + sequence.string() +
                  " --serial F1 --serial F2 --serial F3 --serial F4 --operator OP-18 -o " +
                  fixture.string());
  ASSERT_TRUE(four.exit_code >= 0 && four.exit_code <= 2) << four.out;
  // The document bound first: a range-for over .at() of a temporary reads freed memory (the
  // full sanitized run found it).
  const nlohmann::json fixture_record = ReadJson(fixture / "fixture.json");
  for (const auto& unit : fixture_record.at("units"))
    EXPECT_EQ(
        ReadJson(fixture / unit.at("folder").get<std::string>() / "session.json").at("operator"),
        "OP-18")
        << unit.dump();

  const fs::path killed_dir = work / "killed";
  const Output killed = RunBenchWith(
      kNoPdf + " HRGBENCH_TEST_KILL_AT=run.end",
      "run --station " + StationWithoutStore(work, "station-sim.toml").string() + " --sequence " +
          sequence.string() + " --serial SN-OR --operator OP-19 -o " + killed_dir.string());
  ASSERT_EQ(killed.exit_code, kKilled) << killed.out;
  const Output resumed =
      RunBenchWith(kNoPdf, "resume " + killed_dir.string() + " --operator OP-20");
  ASSERT_TRUE(resumed.exit_code >= 0 && resumed.exit_code <= 2) << resumed.out;
  const nlohmann::json record = ReadJson(killed_dir / "session.json");
  EXPECT_EQ(record.at("operator"), "OP-19");
  ASSERT_EQ(record.at("resumed_at").size(), 1u);
  EXPECT_EQ(record.at("resumed_at")[0].at("operator"), "OP-20");

  const Output refused = RunBenchWith(
      kNoPdf, "run --station " + StationWithoutStore(work, "station-sim.toml").string() +
                  " --sequence " + sequence.string() + " --serial SN-OX --operator ../x -o " +
                  (work / "refused").string());
  EXPECT_EQ(refused.exit_code, 4) << refused.out;
  EXPECT_NE(refused.out.find("--operator: the operator id"), std::string::npos) << refused.out;
  EXPECT_FALSE(fs::exists(work / "refused"));
}

namespace {

// ShortSequence with the operator's two steps of the production sequence.
fs::path ShortSequenceWithPrompts(const fs::path& work) {
  const fs::path path = ShortSequence(work);
  std::ofstream(path, std::ios::app)
      << "\n[[prompts]]\nid = \"mount\"\nat = \"start\"\ntext = \"Mount the unit.\"\n"
         "\n[[prompts]]\nid = \"remove\"\nat = \"end\"\ntext = \"Take it off.\"\n";
  return path;
}

}  // namespace

// Issue 26 §1: a sequence with prompts and nobody to answer them is refused before anything
// starts (stdin is not a terminal), naming what to do; a bad --prompts is refused too.
TEST(BenchProgram, PromptsWithNobodyToAnswerThemAreRefusedBeforeAnythingStarts) {
  const fs::path work = FreshDir("prompts-refused");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  fs::create_directories(work);
  const std::string run =
      "run --station " + StationWithoutStore(work, "station-sim.toml").string() + " --sequence " +
      ShortSequenceWithPrompts(work).string() + " --serial SN-PR -o " + (work / "s").string();
  const Output nobody = RunBench(run + " < /dev/null");
  EXPECT_EQ(nobody.exit_code, 4) << nobody.out;
  EXPECT_NE(nobody.out.find("2 operator prompt(s) ([[prompts]]) and no terminal to answer them on: "
                            "run it on a terminal, from the panel, or with --prompts confirm"),
            std::string::npos)
      << nobody.out;
  EXPECT_FALSE(fs::exists(work / "s"));
  const Output bogus = RunBench(run + " --prompts sometimes < /dev/null");
  EXPECT_EQ(bogus.exit_code, 4) << bogus.out;
  EXPECT_NE(bogus.out.find("--prompts: expected terminal, confirm or fd:N, got 'sometimes'"),
            std::string::npos)
      << bogus.out;
  const Output closed = RunBench(run + " --prompts fd:57 < /dev/null");
  EXPECT_EQ(closed.exit_code, 4) << closed.out;
  EXPECT_NE(closed.out.find("file descriptor 57 is not open"), std::string::npos) << closed.out;
  EXPECT_FALSE(fs::exists(work / "s"));
}

// --prompts confirm: every prompt answered at once and recorded as answered by nobody ("auto");
// --prompts fd:N: JSON lines, an answer to another prompt ignored, recorded with who answered.
TEST(BenchProgram, PromptsAnsweredAutomaticallyOrFromAPipeAreRecordedWithWhoAndHow) {
  const fs::path work = FreshDir("prompts-answered");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  fs::create_directories(work);
  const std::string run = "run --station " +
                          StationWithoutStore(work, "station-sim.toml").string() + " --sequence " +
                          ShortSequenceWithPrompts(work).string() + " --serial SN-PA";
  const Output automatic =
      RunBenchWith(kNoPdf, run + " -o " + (work / "auto").string() + " --prompts confirm");
  EXPECT_NE(automatic.exit_code, 4) << automatic.out;
  EXPECT_NE(automatic.exit_code, 3) << automatic.out;
  auto record = hrgbench::session::ReadSessionRecord(work / "auto");
  ASSERT_TRUE(record.has_value()) << record.error().ToString();
  ASSERT_EQ(record->prompts.size(), 2u);
  for (const hrgbench::session::PromptRecord& prompt : record->prompts) {
    EXPECT_EQ(prompt.answer, "confirmed");
    EXPECT_EQ(prompt.how, "auto");
    EXPECT_EQ(prompt.by, "");
  }

  std::ofstream(work / "answers.jsonl") << R"({"id":"remove","answer":"confirm","by":"OP-EARLY"})"
                                        << "\n"
                                        << R"({"id":"mount","answer":"confirm","by":"OP-P"})"
                                        << "\n"
                                        << R"({"id":"remove","answer":"abort","by":"OP-Q"})"
                                        << "\n";
  const Output piped = RunBenchWith(kNoPdf, run + " -o " + (work / "piped").string() +
                                                " --operator OP-P --prompts fd:5 5< " +
                                                (work / "answers.jsonl").string());
  EXPECT_EQ(piped.exit_code, 3) << piped.out;  // the last answer aborts
  EXPECT_NE(piped.out.find("answer ignored (open prompt 'mount')"), std::string::npos) << piped.out;
  record = hrgbench::session::ReadSessionRecord(work / "piped");
  ASSERT_TRUE(record.has_value()) << record.error().ToString();
  ASSERT_EQ(record->prompts.size(), 2u);
  EXPECT_EQ(record->prompts[0].by, "OP-P");
  EXPECT_EQ(record->prompts[0].how, "panel");
  EXPECT_EQ(record->prompts[1].answer, "aborted");
  EXPECT_EQ(record->prompts[1].by, "OP-Q");
  ASSERT_TRUE(record->outcome.has_value());
  EXPECT_EQ(record->outcome->reason, "aborted by OP-Q at prompt 'remove'");
}

namespace {

// A report job record's state ("" when it has none). Not json::value(): GCC 12 at -O2 reports a
// false "potential null pointer dereference" in it.
std::string StateOf(const nlohmann::json& job) {
  if (!job.is_object()) return {};
  const auto state = job.find("state");
  if (state == job.end() || !state->is_string()) return {};
  return *state->get_ptr<const std::string*>();
}

// The report job's record as the job left it, once it is no longer "running" (or after `limit`).
nlohmann::json WaitForReportJob(const fs::path& session, std::chrono::seconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  nlohmann::json job;
  do {
    job = ReadJson(session / "report" / "job.json");
    if (job.is_object() && StateOf(job) != "running") return job;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  } while (std::chrono::steady_clock::now() < until);
  return job;
}

// An environment variable for the programs a test starts, restored at scope end.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() { ::unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
};

std::string PaperRun(const fs::path& dir, const std::string& serial) {
  return "run --station " + (kConfigs / "station-sim.toml").string() + " --sequence " +
         (kConfigs / "sequence-paper.toml").string() + " --serial " + serial + " -o " +
         dir.string();
}

}  // namespace

// Issue 27 §4: with --report background the program exits at the outcome (and the upload), and a
// job of its own writes the report after it. Chromium here is a stand-in that waits for a gate
// file: the program has exited while the job is provably still inside the report.
TEST(BenchProgram, AReportInTheBackgroundIsWrittenAfterTheProgramHasExited) {
  const fs::path work = FreshDir("report-background");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  fs::create_directories(work);
  const fs::path gate = work / "gate";
  const fs::path chromium = work / "chromium-at-the-gate";
  std::ofstream(chromium) << "#!/bin/sh\nn=0\nwhile [ ! -e " << gate.string()
                          << " ] && [ $n -lt 1200 ]; do sleep 0.1; n=$((n+1)); done\nexit 1\n";
  fs::permissions(chromium, fs::perms::owner_all);
  const ScopedEnv fake_chromium("HRGBENCH_CHROMIUM", chromium.string());
  const fs::path dir = work / "session";
  const JsonOutput run = RunBenchJson(PaperRun(dir, "BG-1") + " --report background --json");
  ASSERT_FALSE(run.doc.is_discarded()) << run.text;
  EXPECT_EQ(run.exit_code, 0) << run.doc.dump(1);
  EXPECT_EQ(run.doc.at("outcome"), "PASS");
  EXPECT_EQ(run.doc.at("report"), (dir / "report" / "report.html").string());
  ASSERT_TRUE(run.doc.at("report_job").is_object()) << run.doc.dump(1);
  const int pid = run.doc.at("report_job").at("pid");
  EXPECT_EQ(run.doc.at("report_job").at("state_file"), (dir / "report" / "job.json").string());
  // The program has exited; the job is at Chromium's gate: running, no PDF yet.
  const nlohmann::json at_exit = ReadJson(dir / "report" / "job.json");
  ASSERT_TRUE(at_exit.is_object());
  EXPECT_EQ(at_exit.at("state"), "running");
  EXPECT_EQ(at_exit.at("pid"), pid);
  EXPECT_FALSE(fs::exists(dir / "report" / "report.pdf"));
  const std::string record = ReadText(dir / "session.json");
  std::ofstream(gate) << "go\n";
  const nlohmann::json job = WaitForReportJob(dir, std::chrono::seconds(300));
  ASSERT_EQ(StateOf(job), "written") << job.dump(1);
  EXPECT_TRUE(fs::is_regular_file(dir / "report" / "report.html"));
  EXPECT_FALSE(job.at("ended").is_null());
  const std::string html = (dir / "report" / "report.html").string();
  const std::vector<std::string> files = job.at("files").get<std::vector<std::string>>();
  EXPECT_NE(std::find(files.begin(), files.end(), html), files.end()) << job.dump(1);
  // The job's output (the PDF it could not print is a warning) is where its record says.
  ASSERT_EQ(job.at("log"), (dir / "report" / "job.log").string());
  EXPECT_NE(ReadText(dir / "report" / "job.log").find("PDF"), std::string::npos)
      << ReadText(dir / "report" / "job.log");
  // The closed record is the job's input, never its output.
  EXPECT_EQ(ReadText(dir / "session.json"), record);

  // --report none: no report and no job; hrg-report makes it later.
  const fs::path none = work / "none";
  const JsonOutput quiet = RunBenchJson(PaperRun(none, "BG-2") + " --report none --json");
  EXPECT_EQ(quiet.exit_code, 0) << quiet.text;
  EXPECT_TRUE(quiet.doc.at("report").is_null());
  EXPECT_TRUE(quiet.doc.at("report_job").is_null());
  EXPECT_FALSE(fs::exists(none / "report"));
}

// A report job killed before it wrote anything (kill -9, a power cut) leaves a record that reads
// as interrupted; resume of the closed session writes the report, and keeps the record as it was.
TEST(BenchProgram, AReportJobKilledMidwayIsInterruptedAndResumeWritesTheReport) {
  const fs::path work = FreshDir("report-job-killed");
  const hrgbench::testing::RemovedAtEnd removes_work(work);
  const fs::path dir = work / "session";
  int pid = 0;
  {
    const ScopedEnv kill_the_job("HRGBENCH_TEST_KILL_AT", "report.job");
    const ScopedEnv no_pdf("HRGBENCH_CHROMIUM", "/bin/false");
    const JsonOutput run = RunBenchJson(PaperRun(dir, "BG-3") + " --report background --json");
    ASSERT_FALSE(run.doc.is_discarded()) << run.text;
    EXPECT_EQ(run.exit_code, 0) << run.doc.dump(1);
    ASSERT_TRUE(run.doc.at("report_job").is_object()) << run.doc.dump(1);
    pid = run.doc.at("report_job").at("pid");
  }
  // The job is gone (its parent exited: init reaps it); its record still says "running".
  for (int i = 0; i < 300 && ::kill(pid, 0) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_NE(::kill(pid, 0), 0) << "the report job " << pid << " is still running";
  EXPECT_EQ(ReadJson(dir / "report" / "job.json").at("state"), "running");
  EXPECT_FALSE(fs::exists(dir / "report" / "report.html"));
  const std::string record = ReadText(dir / "session.json");
  const ScopedEnv no_pdf("HRGBENCH_CHROMIUM", "/bin/false");
  const JsonOutput resumed = RunBenchJson("resume " + dir.string() + " --json");
  ASSERT_FALSE(resumed.doc.is_discarded()) << resumed.text;
  EXPECT_EQ(resumed.exit_code, 0) << resumed.doc.dump(1);
  EXPECT_EQ(resumed.doc.at("report"), (dir / "report" / "report.html").string());
  EXPECT_TRUE(resumed.doc.at("report_job").is_null());
  EXPECT_TRUE(fs::is_regular_file(dir / "report" / "report.html"));
  EXPECT_EQ(ReadText(dir / "session.json"), record);
}
