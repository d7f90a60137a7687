// Issue 25 row 12, its second half: a panel session whose process was killed (kill -9) left its
// record "running", the panel showed only {"signal":9} and offered nothing. The panel now says the
// session is interrupted and why, and POST /api/resume continues it with `hrg-bench resume`.
#include <dirent.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "panel_session_support.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;
using namespace hrgbench::testing::panel;
using namespace std::chrono_literals;

// The session's process: the panel runs in this test's process, so its child is ours, and the
// one child whose command line is `hrg-bench run ...`. -1 when there is none.
pid_t SessionChild() {
  DIR* proc = ::opendir("/proc");
  if (proc == nullptr) return -1;
  pid_t found = -1;
  while (const dirent* entry = ::readdir(proc)) {
    const std::string name = entry->d_name;
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat("/proc/" + name + "/stat");
    std::string line;
    std::getline(stat, line);
    // pid (comm) state ppid ...: comm may hold spaces, so read after its closing parenthesis.
    const std::size_t close = line.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(line.substr(close + 1));
    char state = 0;
    pid_t ppid = 0;
    rest >> state >> ppid;
    if (ppid != ::getpid()) continue;
    std::ifstream cmdline("/proc/" + name + "/cmdline");
    std::string argv0, argv1;
    std::getline(cmdline, argv0, '\0');
    std::getline(cmdline, argv1, '\0');
    if (fs::path(argv0).filename() == "hrg-bench" && argv1 == "run") found = std::stoi(name);
  }
  ::closedir(proc);
  return found;
}

// The record's complete runs (id -> its CSV's bytes), once `n` of them exist (hang guard `guard`).
std::map<int, std::string> WaitForCompleteRuns(const fs::path& folder, std::size_t n,
                                               std::chrono::seconds guard) {
  const auto end = std::chrono::steady_clock::now() + guard;
  while (std::chrono::steady_clock::now() < end) {
    const nlohmann::json record = ReadRecord(folder);
    std::map<int, std::string> complete;
    if (record.is_object() && record.contains("runs"))
      for (const auto& run : record["runs"])
        if (run.value("status", "") == "complete") complete[run.value("id", 0)] = "";
    if (complete.size() >= n) {
      for (auto& [id, bytes] : complete) {
        char file[32];
        std::snprintf(file, sizeof file, "run-%03d.csv", id);
        std::ifstream in(folder / "runs" / file, std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        bytes = text.str();
      }
      return complete;
    }
    std::this_thread::sleep_for(20ms);
  }
  return {};
}

nlohmann::json FullState(const Panel& panel) {
  const Reply reply = Exchange(panel.port(), Get("/api/state", panel.port()));
  return reply.status == 200 ? Json(reply.body) : nlohmann::json();
}

TEST(PanelSession, AKilledSessionIsShownInterruptedAndResumesToItsEndKeepingItsRuns) {
  const fs::path dir = FreshDir();
  {
    // The paper's five short runs at 20× real time: seconds per run, so the kill lands mid-way.
    Panel panel(dir, FreePort(), kBench, PacedStation(dir / "station", 20.0),
                kConfigs / "sequence-paper.toml");
    ASSERT_TRUE(panel.Ready());
    const Reply nothing =
        Exchange(panel.port(), Post("/api/resume", panel.host(), panel.origin(), "{}"));
    EXPECT_EQ(nothing.status, 409) << nothing.body;  // nothing has run

    const Reply started =
        Exchange(panel.port(),
                 Post("/api/start", panel.host(), panel.origin(),
                      R"({"serial":"SN-RESUME","sequence":0,"limits":null,"operator":"OP-T"})"));
    ASSERT_EQ(started.status, 200) << started.body;
    const std::string name = Json(started.body).value("session", "");
    const fs::path folder = dir / "sessions" / name;

    // Two runs done and the third under way: then the session's process is killed.
    const std::map<int, std::string> kept = WaitForCompleteRuns(folder, 2, 120s);
    const pid_t child = SessionChild();
    ASSERT_GT(child, 0) << "no `hrg-bench run` child of the panel";
    ASSERT_EQ(::kill(child, SIGKILL), 0);
    ASSERT_EQ(kept.size(), 2u) << "the session did not get through two runs";

    const nlohmann::json killed = WaitForSessionEnd(panel, 60s);
    ASSERT_TRUE(killed.is_object()) << "the panel's state did not answer";
    EXPECT_EQ(killed["exit"], nlohmann::json({{"signal", 9}})) << killed.dump();
    EXPECT_EQ(ReadRecord(folder).value("state", ""), "running");
    const nlohmann::json state = FullState(panel);
    ASSERT_TRUE(state.is_object());
    const nlohmann::json interrupted = state["interrupted"];
    ASSERT_TRUE(interrupted.is_object()) << state.dump();
    EXPECT_EQ(interrupted["session"], name);
    EXPECT_EQ(interrupted["unit"], "SN-RESUME");
    const std::string reason = interrupted.value("reason", "");
    EXPECT_NE(reason.find("killed by signal 9 (SIGKILL)"), std::string::npos) << reason;

    // Only a folder of the sessions folder with an open record, and only from the panel's own
    // origin (or with its token).
    for (const char* body : {R"({"session":"../sessions"})", R"({"session":"/tmp"})",
                             R"({"session":"SN-NONE-20260101T000000Z"})"}) {
      const Reply refused =
          Exchange(panel.port(), Post("/api/resume", panel.host(), panel.origin(), body));
      EXPECT_EQ(refused.status, 404) << body << ": " << refused.body;
    }
    const Reply cross =
        Exchange(panel.port(), Post("/api/resume", panel.host(), "http://attacker.example", "{}"));
    EXPECT_EQ(cross.status, 403) << cross.body;
    const Reply no_origin = Exchange(panel.port(), Post("/api/resume", panel.host(), "", "{}"));
    EXPECT_EQ(no_origin.status, 403) << no_origin.body;

    const Reply resumed =
        Exchange(panel.port(), Post("/api/resume", panel.host(), panel.origin(), "{}"));
    ASSERT_EQ(resumed.status, 200) << resumed.body;
    EXPECT_EQ(Json(resumed.body).value("session", ""), name);
    const Reply twice =
        Exchange(panel.port(), Post("/api/resume", panel.host(), panel.origin(), "{}"));
    EXPECT_EQ(twice.status, 409) << twice.body;  // one session at a time

    const nlohmann::json done = WaitForSessionEnd(panel, 300s);
    ASSERT_TRUE(done.is_object()) << "the panel's state did not answer";
    ASSERT_FALSE(done.value("running", true)) << "the resume did not end: " << done.dump();
    EXPECT_EQ(done["exit"], nlohmann::json({{"exit_code", 0}})) << done.dump();  // PASS
    EXPECT_EQ(done.value("resume", false), true);
    EXPECT_TRUE(FullState(panel)["interrupted"].is_null());

    const nlohmann::json record = ReadRecord(folder);
    ASSERT_TRUE(record.is_object()) << "no record";
    EXPECT_EQ(record["state"], "closed");
    EXPECT_EQ(record["outcome"]["kind"], "PASS") << record["outcome"].dump();
    ASSERT_TRUE(record.contains("resumed_at"));
    EXPECT_EQ(record["resumed_at"].size(), 1u);
    std::size_t complete = 0;
    for (const auto& run : record["runs"]) complete += run.value("status", "") == "complete";
    EXPECT_EQ(complete, 5u) << record["runs"].dump();
    // The runs completed before the kill are the same files, byte for byte.
    const std::map<int, std::string> after = WaitForCompleteRuns(folder, 5, 1s);
    for (const auto& [id, bytes] : kept) {
      ASSERT_TRUE(after.contains(id)) << "run " << id;
      EXPECT_FALSE(bytes.empty()) << "run " << id;
      EXPECT_TRUE(after.at(id) == bytes) << "run " << id << " changed";
    }
    const Reply closed = Exchange(panel.port(), Post("/api/resume", panel.host(), panel.origin(),
                                                     R"({"session":")" + name + R"("})"));
    EXPECT_EQ(closed.status, 409) << closed.body;  // a closed record is not re-opened
  }
  fs::remove_all(dir);
}

// A panel restarted after its session's process died knows nothing of that session: it names no
// interrupted session, and resumes the folder when asked for it by name (its record is open).
TEST(PanelSession, ARestartedPanelResumesAnOpenRecordOfItsSessionsFolderByName) {
  const fs::path dir = FreshDir();
  const fs::path station = PacedStation(dir / "station", 20.0);
  std::string name;
  std::map<int, std::string> kept;
  {
    Panel panel(dir, FreePort(), kBench, station, kConfigs / "sequence-paper.toml");
    ASSERT_TRUE(panel.Ready());
    const Reply started =
        Exchange(panel.port(),
                 Post("/api/start", panel.host(), panel.origin(),
                      R"({"serial":"SN-RESTART","sequence":0,"limits":null,"operator":"OP-T"})"));
    ASSERT_EQ(started.status, 200) << started.body;
    name = Json(started.body).value("session", "");
    kept = WaitForCompleteRuns(dir / "sessions" / name, 1, 120s);
    const pid_t child = SessionChild();
    ASSERT_GT(child, 0) << "no `hrg-bench run` child of the panel";
    ASSERT_EQ(::kill(child, SIGKILL), 0);
    ASSERT_EQ(kept.size(), 1u) << "the session did not get through a run";
    ASSERT_TRUE(WaitForSessionEnd(panel, 60s).is_object());
  }
  {
    Panel panel(dir, FreePort(), kBench, station, kConfigs / "sequence-paper.toml");
    ASSERT_TRUE(panel.Ready());
    EXPECT_TRUE(FullState(panel)["interrupted"].is_null());
    const Reply unnamed =
        Exchange(panel.port(), Post("/api/resume", panel.host(), panel.origin(), "{}"));
    EXPECT_EQ(unnamed.status, 409) << unnamed.body;
    const Reply resumed = Exchange(panel.port(), Post("/api/resume", panel.host(), panel.origin(),
                                                      R"({"session":")" + name + R"("})"));
    ASSERT_EQ(resumed.status, 200) << resumed.body;
    const nlohmann::json done = WaitForSessionEnd(panel, 300s);
    ASSERT_TRUE(done.is_object()) << "the panel's state did not answer";
    ASSERT_FALSE(done.value("running", true)) << "the resume did not end: " << done.dump();
    EXPECT_EQ(done["exit"], nlohmann::json({{"exit_code", 0}})) << done.dump();
    EXPECT_EQ(done.value("unit", ""), "SN-RESTART");  // from the record
    const nlohmann::json record = ReadRecord(dir / "sessions" / name);
    EXPECT_EQ(record["state"], "closed");
    EXPECT_EQ(record["outcome"]["kind"], "PASS") << record["outcome"].dump();
    const std::map<int, std::string> after = WaitForCompleteRuns(dir / "sessions" / name, 5, 1s);
    for (const auto& [id, bytes] : kept) {
      ASSERT_TRUE(after.contains(id)) << "run " << id;
      EXPECT_TRUE(after.at(id) == bytes) << "run " << id << " changed";
    }
  }
  fs::remove_all(dir);
}

// Issue 26 §1: a fixture started from the panel and killed mid-run is shown interrupted (which
// units are still open) and resumed from the panel to its end: every unit closed, the runs
// completed before the kill unchanged, the page told the units again.
TEST(PanelSession, AKilledFixtureIsShownInterruptedAndResumesEveryUnit) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir, FreePort(), kBench,
                PacedStation(dir / "station", 20.0, "station-sim-fixture.toml"),
                kConfigs / "sequence-paper.toml");
    ASSERT_TRUE(panel.Ready());
    const Reply started =
        Exchange(panel.port(),
                 Post("/api/start", panel.host(), panel.origin(),
                      R"({"serials":{"A":"FK-A","B":"FK-B","C":"FK-C","D":"FK-D"},"sequence":0,)"
                      R"("limits":null,"operator":"OP-T"})"));
    ASSERT_EQ(started.status, 200) << started.body;
    const std::string name = Json(started.body).value("session", "");
    const fs::path folder = dir / "sessions" / name;
    const std::map<int, std::string> kept = WaitForCompleteRuns(folder / "A-FK-A", 1, 120s);
    const pid_t child = SessionChild();
    ASSERT_GT(child, 0) << "no `hrg-bench run` child of the panel";
    ASSERT_EQ(::kill(child, SIGKILL), 0);
    ASSERT_EQ(kept.size(), 1u) << "the fixture did not get through a run";
    ASSERT_TRUE(WaitForSessionEnd(panel, 60s).is_object());

    const nlohmann::json interrupted = FullState(panel)["interrupted"];
    ASSERT_TRUE(interrupted.is_object()) << FullState(panel).dump();
    EXPECT_EQ(interrupted["session"], name);
    EXPECT_EQ(interrupted["unit"], "fixture");
    const std::string reason = interrupted.value("reason", "");
    EXPECT_NE(reason.find("killed by signal 9 (SIGKILL) before every unit's record was closed "
                          "(A FK-A, B FK-B, C FK-C, D FK-D)"),
              std::string::npos)
        << reason;

    const Reply resumed = Exchange(
        panel.port(), Post("/api/resume", panel.host(), panel.origin(), R"({"operator":"OP-R"})"));
    ASSERT_EQ(resumed.status, 200) << resumed.body;
    const nlohmann::json running = SessionState(panel);
    EXPECT_EQ(running["units"].size(), 4u) << running.dump();
    const nlohmann::json done = WaitForSessionEnd(panel, 300s);
    ASSERT_TRUE(done.is_object()) << "the panel's state did not answer";
    ASSERT_FALSE(done.value("running", true)) << "the resume did not end: " << done.dump();
    EXPECT_EQ(done["exit"], nlohmann::json({{"exit_code", 0}})) << done.dump();
    EXPECT_TRUE(FullState(panel)["interrupted"].is_null());
    for (const char* unit : {"A-FK-A", "B-FK-B", "C-FK-C", "D-FK-D"}) {
      const nlohmann::json record = ReadRecord(folder / unit);
      EXPECT_EQ(record.value("state", ""), "closed") << unit;
    }
    const std::map<int, std::string> after = WaitForCompleteRuns(folder / "A-FK-A", 5, 1s);
    for (const auto& [id, bytes] : kept) {
      ASSERT_TRUE(after.contains(id)) << "run " << id;
      EXPECT_TRUE(after.at(id) == bytes) << "run " << id << " changed";
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrgbench::app
