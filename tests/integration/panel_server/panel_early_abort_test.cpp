// Issue 25 row 12: an Abort within ~100 ms of Start reached hrg-bench before its signal handlers
// existed and killed it by SIGINT's default action: no record, the panel showed {"signal":2}.
// The session's program now holds SIGINT from its exec until its handlers exist.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "panel_session_support.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;
using namespace hrgbench::testing::panel;
using namespace std::chrono_literals;

TEST(PanelSession, AnAbortRightAfterStartEndsTheSessionAbortedWithItsRecord) {
  const fs::path dir = FreshDir();
  {
    Panel panel(dir, FreePort(), kBench, RealTimeStation(dir / "station"));
    ASSERT_TRUE(panel.Ready());
    const Reply started =
        Exchange(panel.port(),
                 Post("/api/start", panel.host(), panel.origin(),
                      R"({"serial":"SN-EARLY","sequence":0,"limits":null,"operator":"OP-T"})"));
    ASSERT_EQ(started.status, 200) << started.body;
    const Reply abort =
        Exchange(panel.port(), Post("/api/abort", panel.host(), panel.origin(), "{}"));
    ASSERT_EQ(abort.status, 200) << abort.body;

    const nlohmann::json session = WaitForSessionEnd(panel, 60s);
    ASSERT_TRUE(session.is_object()) << "the panel's state did not answer";
    ASSERT_FALSE(session.value("running", true)) << session.dump();
    EXPECT_EQ(session["exit"], nlohmann::json({{"exit_code", 3}})) << session.dump();  // ABORTED
    const nlohmann::json record =
        ReadRecord(dir / "sessions" / Json(started.body).value("session", ""));
    ASSERT_TRUE(record.is_object()) << "no record";
    EXPECT_EQ(record["outcome"]["kind"], "ABORTED") << record["outcome"].dump();
    const std::string reason = record["outcome"].value("reason", "");
    EXPECT_EQ(reason.rfind("aborted by operator", 0), 0u) << reason;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrgbench::app
