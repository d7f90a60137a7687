// Operator prompts in the record (issue 26 §1): each prompt shown is in session.json at once (a
// process that dies with one open leaves it open, and resume says it was interrupted), answered
// with who, how and when, and read back by the typed reader.

#include <gtest/gtest.h>

#include <fstream>

#include "hrgbench/session/session_record.hpp"
#include "hrgbench/session/session_recorder.hpp"
#include "record_test_dir.hpp"
#include "synthetic_gyro_record.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::ScratchDir;
using testing::SyntheticHeader;

json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  return json::parse(in);
}

const PromptShown kMount{"mount", "start", "Mount the unit.", ""};
const PromptShown kCable{"cable", "before run 2", "Swap the cable.",
                         "09ecb6ebc8bcefc733f6f2ec44f791abeed6a99edf0cc31519637898aebd52d8"};

TEST(SessionRecorderPrompts, AShownPromptIsOnDiskBeforeItIsAnsweredThenAnsweredWithWhoAndHow) {
  ScratchDir scratch("recorder_prompts");
  const fs::path dir = scratch / "s";
  auto recorder = SessionRecorder::Create(dir, SyntheticHeader(2));
  ASSERT_TRUE(recorder.has_value());
  ASSERT_TRUE(recorder->BeginPrompt(kMount).has_value());
  json doc = ReadJson(dir / "session.json");
  ASSERT_EQ(doc["prompts"].size(), 1u);
  EXPECT_EQ(doc["prompts"][0]["id"], "mount");
  EXPECT_TRUE(doc["prompts"][0]["shown"]["utc"].is_string());
  EXPECT_FALSE(doc["prompts"][0].contains("answer"));  // open: nobody has answered yet
  EXPECT_TRUE(doc["prompts"][0]["image_sha256"].is_null());
  ASSERT_TRUE(recorder->EndPrompt({kPromptConfirmed, "OP-7", "panel"}).has_value());
  ASSERT_TRUE(recorder->BeginPrompt(kCable).has_value());
  ASSERT_TRUE(recorder->EndPrompt({kPromptAborted, "OP-8", "terminal"}).has_value());
  ASSERT_TRUE(
      recorder->Close({OutcomeKind::kAborted, "aborted by OP-8 at prompt 'cable'", {}, {}, {}})
          .has_value());

  auto record = session::ReadSessionRecord(dir);
  ASSERT_TRUE(record.has_value()) << record.error().ToString();
  ASSERT_EQ(record->prompts.size(), 2u);
  const session::PromptRecord& mount = record->prompts[0];
  EXPECT_EQ(mount.id, "mount");
  EXPECT_EQ(mount.at, "start");
  EXPECT_EQ(mount.text, "Mount the unit.");
  EXPECT_EQ(mount.answer, kPromptConfirmed);
  EXPECT_EQ(mount.by, "OP-7");
  EXPECT_EQ(mount.how, "panel");
  ASSERT_TRUE(mount.shown && mount.answered);
  EXPECT_LE(mount.shown->utc, mount.answered->utc);  // one fixed-width UTC form: text order
  ASSERT_TRUE(mount.shown->monotonic_ns && mount.answered->monotonic_ns);
  EXPECT_LE(*mount.shown->monotonic_ns, *mount.answered->monotonic_ns);
  const session::PromptRecord& cable = record->prompts[1];
  EXPECT_EQ(cable.at, "before run 2");
  EXPECT_EQ(cable.image_sha256, kCable.image_sha256);
  EXPECT_EQ(cable.answer, kPromptAborted);
  EXPECT_EQ(cable.by, "OP-8");
  EXPECT_EQ(cable.how, "terminal");
}

TEST(SessionRecorderPrompts, ClosingWithAPromptOpenRecordsItInterruptedWithTheReason) {
  ScratchDir scratch("recorder_prompt_close");
  const fs::path dir = scratch / "s";
  auto recorder = SessionRecorder::Create(dir, SyntheticHeader(1));
  ASSERT_TRUE(recorder.has_value());
  ASSERT_TRUE(recorder->BeginPrompt(kMount).has_value());
  ASSERT_TRUE(recorder
                  ->Close({OutcomeKind::kAborted,
                           "aborted by operator while prompt 'mount' was open",
                           {},
                           {},
                           {}})
                  .has_value());
  auto record = session::ReadSessionRecord(dir);
  ASSERT_TRUE(record.has_value()) << record.error().ToString();
  ASSERT_EQ(record->prompts.size(), 1u);
  EXPECT_EQ(record->prompts[0].answer, kPromptInterrupted);
  EXPECT_EQ(record->prompts[0].by, "");
  EXPECT_EQ(record->prompts[0].reason, "aborted by operator while prompt 'mount' was open");
  EXPECT_TRUE(record->prompts[0].answered.has_value());
}

TEST(SessionRecorderPrompts, AResumeSaysAPromptTheProcessDiedWithWasInterrupted) {
  ScratchDir scratch("recorder_prompt_resume");
  const fs::path dir = scratch / "s";
  {
    auto recorder = SessionRecorder::Create(dir, SyntheticHeader(1));
    ASSERT_TRUE(recorder.has_value());
    ASSERT_TRUE(recorder->BeginPrompt(kMount).has_value());
  }  // destroyed without Close: as a kill -9 leaves it
  auto resumed = SessionRecorder::OpenForResume(dir);
  ASSERT_TRUE(resumed.has_value()) << resumed.error().ToString();
  const json doc = ReadJson(dir / "session.json");
  EXPECT_EQ(doc["prompts"][0]["answer"], "interrupted");
  EXPECT_EQ(doc["prompts"][0]["reason"], "the process ended while it was open");
  // The resumed session asks again: a new entry, the old one kept.
  ASSERT_TRUE(resumed->BeginPrompt(kMount).has_value());
  ASSERT_TRUE(resumed->EndPrompt({kPromptConfirmed, "OP-9", "panel"}).has_value());
  auto record = session::ReadSessionRecord(dir);
  ASSERT_TRUE(record.has_value()) << record.error().ToString();
  ASSERT_EQ(record->prompts.size(), 2u);
  EXPECT_EQ(record->prompts[1].answer, kPromptConfirmed);
}

TEST(SessionRecorderPrompts, OutOfOrderCallsAndBadAnswersAreRefusedAndWriteNothing) {
  ScratchDir scratch("recorder_prompt_order");
  const fs::path dir = scratch / "s";
  const SessionHeader header = SyntheticHeader(1);
  auto recorder = SessionRecorder::Create(dir, header);
  ASSERT_TRUE(recorder.has_value());
  auto no_prompt = recorder->EndPrompt({kPromptConfirmed, "OP", "panel"});
  ASSERT_FALSE(no_prompt);
  EXPECT_EQ(no_prompt.error().kind, RecordErrorKind::kWrongState);
  auto no_id = recorder->BeginPrompt({"", "start", "x", ""});
  ASSERT_FALSE(no_id);
  EXPECT_EQ(no_id.error().kind, RecordErrorKind::kInvalidArgument);
  ASSERT_TRUE(recorder->BeginPrompt(kMount).has_value());
  auto twice = recorder->BeginPrompt(kCable);
  ASSERT_FALSE(twice);
  EXPECT_EQ(twice.error().kind, RecordErrorKind::kWrongState);
  auto odd = recorder->EndPrompt({"maybe", "OP", "panel"});
  ASSERT_FALSE(odd);
  EXPECT_EQ(odd.error().kind, RecordErrorKind::kInvalidArgument);
  ASSERT_TRUE(recorder->EndPrompt({kPromptConfirmed, "OP", "panel"}).has_value());
  RunStart start;
  start.commanded_omega_rad_s = header.runs[0].commanded_omega_rad_s;
  ASSERT_TRUE(recorder->BeginRun(1, start).has_value());
  auto in_run = recorder->BeginPrompt(kCable);
  ASSERT_FALSE(in_run);
  EXPECT_EQ(in_run.error().kind, RecordErrorKind::kWrongState);
  EXPECT_EQ(ReadJson(dir / "session.json")["prompts"].size(), 1u);
}

TEST(SessionRecorderPrompts, TheReaderRefusesAnAnswerItDoesNotKnow) {
  ScratchDir scratch("recorder_prompt_read");
  const fs::path dir = scratch / "s";
  {
    auto recorder = SessionRecorder::Create(dir, SyntheticHeader(1));
    ASSERT_TRUE(recorder.has_value());
    ASSERT_TRUE(recorder->BeginPrompt(kMount).has_value());
    ASSERT_TRUE(recorder->EndPrompt({kPromptConfirmed, "OP", "panel"}).has_value());
  }
  json doc = ReadJson(dir / "session.json");
  doc["prompts"][0]["answer"] = "perhaps";
  auto record = session::ReadSessionRecord(doc, dir / "session.json");
  ASSERT_FALSE(record.has_value());
  EXPECT_NE(record.error().ToString().find("prompts[0].answer"), std::string::npos)
      << record.error().ToString();
  EXPECT_NE(record.error().ToString().find("perhaps"), std::string::npos)
      << record.error().ToString();
}

}  // namespace
}  // namespace hrgbench::bench
