// The hrg-bench program as an operator (or a crash) meets it: config check, bad configs, an
// unwritable output directory, kill -9 in the middle of a session and `resume`, and Ctrl-C.
// The station is the simulated one, paced at 20× real time so a process can be killed mid-run.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

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
  fs::remove_all(work);
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

// A fixture of four units (station-sim-fixture.toml): killed after two runs, resumed; every unit
// ends with all its runs and its verdict, and fixture.json ties the four together.
TEST(BenchProgram, FixtureKilledMidRunResumesEveryUnit) {
  const fs::path work = FreshDir("fixture-kill9");
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
  fs::remove_all(work);
}

// A unit that never gets ready ends as ERROR; the others PASS; the fixture's exit code is the
// worst unit's. A resume continues that unit only: the others' records are not touched.
TEST(BenchProgram, FixtureResumeContinuesOnlyTheUnitsWithoutAVerdict) {
  const fs::path work = FreshDir("fixture-resume");
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
  fs::remove_all(work);
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
