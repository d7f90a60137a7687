// Operator prompts on the in-process simulated station (issue 26 §1): each asked where the sequence
// says, with the table at rest and every gyro stopped before it is shown; the answer recorded with
// who and how; an "abort" answer, an Abort while one is open and a session with nobody to answer
// all end safely with the reason; on a fixture each prompt is asked once for the table and
// recorded in every unit's record.
#include <algorithm>
#include <cmath>
#include <vector>

#include "bench_test_support.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::testing {
namespace {

namespace fs = std::filesystem;

// Answers from a script, and looks at the hardware at the moment each prompt is shown.
class ScriptedAnswers final : public bench::PromptAnswers {
 public:
  struct Answer {
    bool confirm = true;
    std::string by;
    int waits_first = 0;  // Wait calls answered "not yet" before this answer; -1: never answers
  };
  ScriptedAnswers(std::vector<Answer> script, const bench::BenchHardware* hardware)
      : script_(std::move(script)), hardware_(hardware) {}

  void Show(const bench::PromptRequest& prompt) override {
    shown.push_back(prompt.id + " @ " + prompt.at);
    if (hardware_ == nullptr) return;
    auto status = hardware_->table->ReadStatus();
    table_rate_at_show.push_back(status ? status->measured_rate_rad_s : NAN);
    table_at_rest_at_show.push_back(status && status->mode == hw::RateTableMode::kIdle &&
                                    status->commanded_rate_rad_s == 0.0 && !status->in_motion);
    bool stopped = true;
    for (const bench::UnitHardware& unit : hardware_->units) {
      const hw::GyroMode mode = unit.gyro->State();
      stopped = stopped && (mode == hw::GyroMode::kIdle || mode == hw::GyroMode::kStopped);
    }
    gyros_stopped_at_show.push_back(stopped);
    waits_ = 0;
  }
  std::optional<bench::PromptReply> Wait(std::chrono::milliseconds) override {
    const Answer& answer = script_.at(std::min(shown.size() - 1, script_.size() - 1));
    if (answer.waits_first < 0 || waits_++ < answer.waits_first) return std::nullopt;
    return bench::PromptReply{answer.confirm, answer.by, "test"};
  }

  std::vector<std::string> shown;
  std::vector<double> table_rate_at_show;
  std::vector<bool> table_at_rest_at_show;
  std::vector<bool> gyros_stopped_at_show;

 private:
  std::vector<Answer> script_;
  const bench::BenchHardware* hardware_;
  int waits_ = 0;
};

bench::SequencePrompt Prompt(std::string id, bench::PromptPoint at, int run = 0) {
  bench::SequencePrompt prompt;
  prompt.id = std::move(id);
  prompt.at = at;
  prompt.before_run = run;
  prompt.text = "do " + prompt.id;
  return prompt;
}

// The paper sequence, its runs shortened, with a prompt at the start, before run 2 and at the end.
void ShortWithPrompts(bench::BenchConfigs& c) {
  for (bench::SequenceRun& run : c.sequence.runs) run.free_run_s = 2.0;
  c.sequence.prompts = {Prompt("mount", bench::PromptPoint::kStart),
                        Prompt("cable", bench::PromptPoint::kBeforeRun, 2),
                        Prompt("remove", bench::PromptPoint::kEnd)};
}

std::vector<session::PromptRecord> Prompts(const fs::path& dir) {
  auto record = session::ReadSessionRecord(dir);
  EXPECT_TRUE(record.has_value()) << (record ? "" : record.error().ToString());
  return record ? record->prompts : std::vector<session::PromptRecord>{};
}

TEST(SessionPrompts, EachIsAskedWhereTheSequenceSaysWithTheTableAtRestAndRecorded) {
  std::unique_ptr<app::Station> station;
  auto configs =
      OpenShippedStation("station-sim.toml", "sequence-paper.toml", "", ShortWithPrompts, station);
  ASSERT_TRUE(configs);
  ScriptedAnswers answers({{true, "OP-1", 3}}, &station->hardware());
  std::vector<std::string> phases;
  bench::RunnerOptions options;
  options.unit_serial = "P-1";
  options.prompts = &answers;
  options.simulation = station->simulation();
  options.on_progress = [&](const bench::Progress& p) {
    if (phases.empty() || phases.back() != p.phase) phases.emplace_back(p.phase);
  };
  const fs::path dir = FreshDir("prompts");
  const bench::SessionResult result =
      bench::RunSession(*configs, station->hardware(), dir, options);
  ASSERT_NE(result.outcome, bench::OutcomeKind::kError) << result.reason;
  ASSERT_NE(result.outcome, bench::OutcomeKind::kAborted) << result.reason;
  EXPECT_EQ(answers.shown,
            (std::vector<std::string>{"mount @ start", "cable @ before run 2", "remove @ end"}));
  // Safe before anyone is asked to act: the table idle at zero rate and no longer moving, its
  // reading within its rate noise of zero (the sequence's tolerance is 1e-4 rad/s and one reading
  // later read 1.006e-4: 3 × the tolerance), every gyro stopped (the last run's too, before
  // "remove").
  for (std::size_t i = 0; i < answers.shown.size(); ++i) {
    EXPECT_TRUE(answers.table_at_rest_at_show[i]) << answers.shown[i];
    EXPECT_LE(std::abs(answers.table_rate_at_show[i]),
              3 * configs->sequence.settle.rate_tolerance_rad_s)
        << answers.shown[i];
    EXPECT_TRUE(answers.gyros_stopped_at_show[i]) << answers.shown[i];
  }
  // The start's prompt before the warm-up, the end's before the estimate.
  const auto at = [&](const std::string& phase) {
    return std::find(phases.begin(), phases.end(), phase) - phases.begin();
  };
  EXPECT_LT(at("prompt"), at("warm-up"));
  EXPECT_EQ(phases[phases.size() - 2], "prompt");
  EXPECT_EQ(phases.back(), "estimate");

  const auto prompts = Prompts(dir);
  ASSERT_EQ(prompts.size(), 3u);
  for (const session::PromptRecord& prompt : prompts) {
    EXPECT_EQ(prompt.answer, bench::kPromptConfirmed);
    EXPECT_EQ(prompt.by, "OP-1");
    EXPECT_EQ(prompt.how, "test");
    EXPECT_EQ(prompt.text, "do " + prompt.id);
  }
  EXPECT_EQ(prompts[1].at, "before run 2");
  fs::remove_all(dir);
}

TEST(SessionPrompts, AnAbortAnswerEndsTheSessionAbortedNamingWhoWithTheTableAtZero) {
  std::unique_ptr<app::Station> station;
  auto configs =
      OpenShippedStation("station-sim.toml", "sequence-paper.toml", "", ShortWithPrompts, station);
  ASSERT_TRUE(configs);
  ScriptedAnswers answers({{true, "OP-1", 0}, {false, "OP-2", 1}}, &station->hardware());
  bench::RunnerOptions options;
  options.unit_serial = "P-2";
  options.prompts = &answers;
  const fs::path dir = FreshDir("prompt-abort");
  const bench::SessionResult result =
      bench::RunSession(*configs, station->hardware(), dir, options);
  EXPECT_EQ(result.outcome, bench::OutcomeKind::kAborted);
  EXPECT_EQ(result.reason, "aborted by OP-2 at prompt 'cable'");
  auto record = session::ReadSessionRecord(dir);
  ASSERT_TRUE(record.has_value());
  EXPECT_EQ(record->runs[0].status, bench::kRunComplete);  // run 1 was made, run 2 never began
  EXPECT_EQ(record->runs[1].status, bench::kRunPlanned);
  const auto prompts = Prompts(dir);
  ASSERT_EQ(prompts.size(), 2u);
  EXPECT_EQ(prompts[1].answer, bench::kPromptAborted);
  EXPECT_EQ(prompts[1].by, "OP-2");
  auto status = station->hardware().table->ReadStatus();
  ASSERT_TRUE(status);
  EXPECT_EQ(status->commanded_rate_rad_s, 0.0);
  fs::remove_all(dir);
}

TEST(SessionPrompts, AnAbortWhileAPromptIsOpenStopsSafelyAndRecordsItInterrupted) {
  ScriptedAnswers never({{true, "", -1}}, nullptr);
  const BenchRun run = RunOnSimulatedStation(
      "sequence-paper.toml", "", ShortWithPrompts,
      [](const bench::Progress& p) { return p.phase == "prompt"; }, {}, "station-sim.toml", &never);
  EXPECT_EQ(run.result.outcome, bench::OutcomeKind::kAborted);
  EXPECT_EQ(run.result.reason, "aborted by operator while prompt 'mount' was open");
  const auto prompts = Prompts(run.dir);
  ASSERT_EQ(prompts.size(), 1u);
  EXPECT_EQ(prompts[0].answer, bench::kPromptInterrupted);
  EXPECT_EQ(prompts[0].reason, "aborted by operator while prompt 'mount' was open");
  fs::remove_all(run.dir);
}

TEST(SessionPrompts, WithNobodyToAnswerTheSessionIsRefusedBeforeAnythingMoves) {
  std::unique_ptr<app::Station> station;
  auto configs =
      OpenShippedStation("station-sim.toml", "sequence-paper.toml", "", ShortWithPrompts, station);
  ASSERT_TRUE(configs);
  bench::RunnerOptions options;
  options.unit_serial = "P-3";
  const fs::path dir = FreshDir("prompt-nobody");
  const bench::SessionResult result =
      bench::RunSession(*configs, station->hardware(), dir, options);
  EXPECT_EQ(result.outcome, bench::OutcomeKind::kError);
  EXPECT_NE(result.reason.find("3 operator prompt(s) ([[prompts]]) and nothing to answer them"),
            std::string::npos)
      << result.reason;
  EXPECT_FALSE(fs::exists(dir / "session.json"));
  auto status = station->hardware().table->ReadStatus();
  ASSERT_TRUE(status);
  EXPECT_EQ(status->commanded_rate_rad_s, 0.0);
  fs::remove_all(dir);
}

TEST(SessionPrompts, OnAFixtureEachPromptIsAskedOnceAndRecordedForEveryUnit) {
  ScriptedAnswers answers({{true, "OP-F", 0}}, nullptr);
  const FixtureRun run = RunFixtureOnSimulatedStation("sequence-paper.toml", "", ShortWithPrompts,
                                                      {}, "station-sim-fixture.toml", &answers);
  ASSERT_EQ(run.results.size(), 4u);
  EXPECT_EQ(answers.shown.size(), 3u);
  for (const fs::path& dir : run.dirs) {
    const auto prompts = Prompts(dir);
    ASSERT_EQ(prompts.size(), 3u) << dir;
    EXPECT_EQ(prompts[0].by, "OP-F");
  }
  if (!run.dirs.empty()) fs::remove_all(run.dirs.front().parent_path());
}

}  // namespace
}  // namespace hrgbench::testing
