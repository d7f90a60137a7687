// hrg-bench run --events on the in-process simulated station (faster than real time): the stream
// as a second program reads it, checked against the session.json the same run wrote.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const std::string kBench = std::string(HRGBENCH_BIN_DIR) + "/hrg-bench";
const fs::path kConfigs = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";

fs::path FreshDir(const std::string& stem) {
  std::random_device rd;
  const fs::path dir =
      fs::temp_directory_path() / ("hrgbench-" + stem + "-" + std::to_string(rd()));
  fs::create_directories(dir);
  return dir;
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// station-sim.toml (faster than real time) with the housing warming at 0.1 °C/s: 0.4 °C over a 4 s
// run is 1.6 % of 25 °C, above the sequence's 1 %, so every run is flagged (a warning event).
fs::path DriftingStation(const fs::path& dir) {
  std::string toml = ReadText(kConfigs / "station-sim.toml");
  const std::string drift = "temperature_drift_c_per_s = 0.0";
  toml.replace(toml.find(drift), drift.size(), "temperature_drift_c_per_s = 0.1");
  const fs::path path = dir / "station-drifting.toml";
  std::ofstream(path) << toml;
  return path;
}

// Three 4 s runs at 100 Hz at table rates (δ2 and every ξ determined, so the example limits are
// judged); warm-up accepts the drifting housing; drift flags, never rejects.
fs::path ShortSequence(const fs::path& dir) {
  const fs::path path = dir / "sequence-short.toml";
  std::ofstream(path) << R"([sequence]
name = "events-test"
description = "Three short runs for the event stream test"
[settle]
rate_tolerance_rad_s = 1e-4
dwell_s = 0.2
poll_period_s = 0.05
[timeouts]
settle_s = 60.0
excite_s = 10.0
run_margin_s = 5.0
[warmup]
min_s = 0.0
window_s = 2.0
max_drift_c = 100.0
timeout_s = 60.0
[drift]
max_temperature_change_rel = 0.01
action = "flag"
[capture]
max_sequence_gaps = 0
max_samples_lost = 0
[defaults]
a = 1.0
free_run_s = 4.0
sample_rate_hz = 100
[[runs]]
omega_rad_s = -1.0
b = -0.4
theta_rad = 0.0
[[runs]]
omega_rad_s = 0.3
b = 0.0
theta_rad = 0.9
[[runs]]
omega_rad_s = 1.0
b = 0.4
theta_rad = 1.8
)";
  return path;
}

std::vector<nlohmann::json> ParseLines(const std::string& text) {
  std::vector<nlohmann::json> events;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const nlohmann::json e = nlohmann::json::parse(line, nullptr, false);
    EXPECT_FALSE(e.is_discarded()) << "not JSON: " << line;
    if (!e.is_discarded()) events.push_back(e);
  }
  return events;
}

// Runs hrg-bench with `events_fd` as its fd 3 (stdout and stderr to `log`); returns its pid.
pid_t Spawn(const std::vector<std::string>& args, const fs::path& log, int events_fd) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(out, STDERR_FILENO);
    if (events_fd >= 0) ::dup2(events_fd, 3);
    std::vector<char*> argv{const_cast<char*>(kBench.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(kBench.c_str(), argv.data());
    std::_Exit(127);
  }
  return pid;
}

int Wait(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

nlohmann::json ReadJson(const fs::path& file) { return nlohmann::json::parse(ReadText(file)); }

// Every run of the session has every planned sample, in order, without a gap.
void ExpectEverySample(const fs::path& session) {
  const nlohmann::json doc = ReadJson(session / "session.json");
  ASSERT_EQ(doc["runs"].size(), 3u);
  for (const nlohmann::json& run : doc["runs"]) {
    EXPECT_EQ(run["status"], "complete");
    std::ifstream csv(session / run["file"].get<std::string>());
    std::string line;
    std::getline(csv, line);  // header: seq's place in it
    std::size_t seq_column = 0;
    for (std::size_t at = 0; at < line.find("seq"); ++at) seq_column += line[at] == ',';
    ASSERT_NE(line.find(",seq"), std::string::npos) << line;
    std::int64_t rows = 0;
    while (std::getline(csv, line)) {
      std::size_t start = 0;
      for (std::size_t c = 0; c < seq_column; ++c) start = line.find(',', start) + 1;
      const std::int64_t seq = std::stoll(line.substr(start, line.find(',', start) - start));
      EXPECT_EQ(seq, rows) << run["file"];
      ++rows;
    }
    EXPECT_EQ(rows, 400) << run["file"];  // 4 s at 100 Hz
    EXPECT_EQ(run["end"]["sequence_gaps"], 0);
  }
}

TEST(EventsProgram, EveryTypeInOrderAndAgreeingWithTheRecord) {
  const fs::path work = FreshDir("events");
  const fs::path session = work / "session";
  const fs::path events_file = work / "events.jsonl";
  const pid_t pid =
      Spawn({"run", "--station", DriftingStation(work).string(), "--sequence",
             ShortSequence(work).string(), "--limits", (kConfigs / "limits-example.toml").string(),
             "--serial", "SN-EV1", "-o", session.string(), "--events", events_file.string()},
            work / "run.log", -1);
  const int exit_code = Wait(pid);
  const nlohmann::json doc = ReadJson(session / "session.json");
  EXPECT_EQ(exit_code, doc["outcome"]["exit_code"]) << ReadText(work / "run.log");

  const std::vector<nlohmann::json> events = ParseLines(ReadText(events_file));
  ASSERT_FALSE(events.empty());
  std::map<std::string, int> count;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const nlohmann::json& e = events[i];
    EXPECT_EQ(e["v"], 1);
    EXPECT_EQ(e["seq"], i);  // a file reader loses nothing: 0, 1, 2, ...
    if (i > 0) {
      EXPECT_GE(e["time_unix_s"].get<double>(), events[i - 1]["time_unix_s"].get<double>());
    }
    ++count[e["type"].get<std::string>()];
  }
  for (const char* type : {"session_started", "phase", "progress", "samples", "log", "warning",
                           "run_result", "estimate", "limit", "outcome", "report", "end"})
    EXPECT_GT(count[type], 0) << "no " << type << " event";
  EXPECT_EQ(events.front()["type"], "session_started");
  EXPECT_EQ(events.front()["unit"], "SN-EV1");
  EXPECT_EQ(events.front()["plan"].size(), 3u);
  EXPECT_EQ(events.back()["type"], "end");
  EXPECT_EQ(events.back()["events_lost"], 0);
  EXPECT_EQ(events.back()["events_published"], events.size() - 1);

  // Each run passes through the six phases in order.
  std::map<int, std::vector<std::string>> phases;
  for (const nlohmann::json& e : events)
    if (e["type"] == "phase" && e["run_id"] > 0) phases[e["run_id"]].push_back(e["phase"]);
  ASSERT_EQ(phases.size(), 3u);
  for (const auto& [run, seen] : phases)
    EXPECT_EQ(seen,
              (std::vector<std::string>{"settle", "excite", "ready", "release", "capture", "stop"}))
        << "run " << run;

  // The runs, the limits and the outcome as session.json has them.
  int complete = 0;
  for (const nlohmann::json& e : events) {
    if (e["type"] != "run_result") continue;
    const nlohmann::json& run = doc["runs"][e["run_id"].get<std::size_t>() - 1];
    EXPECT_EQ(e["status"], run["status"]);
    EXPECT_EQ(e["samples"], 400);
    complete += e["status"] == "complete";
    EXPECT_NE(e["reason"].get<std::string>().find("flagged: temperature"), std::string::npos);
  }
  EXPECT_EQ(complete, 3);
  std::set<std::string> limits;
  for (const nlohmann::json& e : events)
    if (e["type"] == "limit") limits.insert(e["quantity"].get<std::string>());
  std::set<std::string> recorded;
  for (const nlohmann::json& l : doc["outcome"]["verdict"]["limits"])
    recorded.insert(l["quantity"].get<std::string>());
  EXPECT_EQ(limits, recorded);
  const auto outcome = std::find_if(events.begin(), events.end(),
                                    [](const nlohmann::json& e) { return e["type"] == "outcome"; });
  ASSERT_NE(outcome, events.end());
  EXPECT_EQ((*outcome)["outcome"], doc["outcome"]["kind"]);
  EXPECT_EQ((*outcome)["reason"], doc["outcome"]["reason"]);
  EXPECT_EQ((*outcome)["complete_runs"], 3);
  const nlohmann::json account = ReadJson(session / "events.json");
  EXPECT_EQ(account["events_lost"], 0);
  EXPECT_EQ(account["events_written"], events.size() - 1);
  EXPECT_TRUE(account["end_written"]);
  fs::remove_all(work);
}

TEST(EventsProgram, AReaderThatStopsReadingLosesEventsNeverSamples) {
  const fs::path work = FreshDir("events-stopped");
  const fs::path session = work / "session";
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ASSERT_GT(::fcntl(fds[1], F_SETPIPE_SZ, 4096), 0);  // the smallest pipe: full after a few events
  const pid_t pid = Spawn({"run", "--station", DriftingStation(work).string(), "--sequence",
                           ShortSequence(work).string(), "--serial", "SN-EV2", "-o",
                           session.string(), "--events", "/dev/fd/3", "--events-queue", "8"},
                          work / "run.log", fds[1]);
  ::close(fds[1]);
  // The reader takes the first line and then stops reading until the session is over.
  std::string first;
  for (char c; ::read(fds[0], &c, 1) == 1 && c != '\n';) first += c;
  EXPECT_EQ(nlohmann::json::parse(first)["type"], "session_started");
  const int exit_code = Wait(pid);
  std::string rest;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof buffer)) > 0;)
    rest.append(buffer, static_cast<std::size_t>(n));
  ::close(fds[0]);

  const nlohmann::json doc = ReadJson(session / "session.json");
  EXPECT_EQ(exit_code, doc["outcome"]["exit_code"]) << ReadText(work / "run.log");
  ExpectEverySample(session);
  const nlohmann::json account = ReadJson(session / "events.json");
  EXPECT_GT(account["events_lost"], 0) << account.dump();
  EXPECT_EQ(
      account["events_written"].get<std::uint64_t>() + account["events_lost"].get<std::uint64_t>(),
      account["events_published"].get<std::uint64_t>());
  // What reached the pipe is whole lines; the lost ones are gaps in seq.
  const std::vector<nlohmann::json> tail = ParseLines(rest);
  std::uint64_t previous = 0;
  for (const nlohmann::json& e : tail) {
    EXPECT_GT(e["seq"].get<std::uint64_t>(), previous);
    previous = e["seq"];
  }
  EXPECT_NE(ReadText(work / "run.log").find("events lost"), std::string::npos);
  fs::remove_all(work);
}

}  // namespace
