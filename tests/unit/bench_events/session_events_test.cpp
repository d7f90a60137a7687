// The session's events as the sequencer's callbacks make them: a phase event at every change (the
// sequencer's "table" is "settle"), progress at a bounded rate, the run's samples decimated to
// about plot_points_per_run, run results with their warnings, and the end of a session (estimate,
// each limit, outcome, report) in that order.
#include "hrgbench/bench/events/session_events.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hrgbench::bench {
namespace {

// Publishes into a pipe and reads back what the stream wrote, parsed.
class Capture {
 public:
  Capture() {
    int fds[2];
    EXPECT_EQ(::pipe2(fds, O_CLOEXEC), 0);
    read_fd_ = fds[0];
    ::fcntl(fds[1], F_SETPIPE_SZ, 1 << 20);  // room for everything a test publishes
    stream_ = EventStream::FromFd(fds[1], 100000);
  }
  ~Capture() { ::close(read_fd_); }
  EventStream& stream() { return *stream_; }
  std::vector<nlohmann::json> Events() {
    stream_->Close(30'000);
    std::string text;
    char buffer[4096];
    for (ssize_t n; (n = ::read(read_fd_, buffer, sizeof buffer)) > 0;)
      text.append(buffer, static_cast<std::size_t>(n));
    std::vector<nlohmann::json> events;
    for (std::size_t start = 0, end; (end = text.find('\n', start)) != std::string::npos;
         start = end + 1)
      events.push_back(nlohmann::json::parse(text.substr(start, end - start)));
    return events;
  }

 private:
  int read_fd_ = -1;
  std::unique_ptr<EventStream> stream_;
};

std::vector<nlohmann::json> OfType(const std::vector<nlohmann::json>& events, const char* type) {
  std::vector<nlohmann::json> out;
  for (const nlohmann::json& e : events)
    if (e["type"] == type) out.push_back(e);
  return out;
}

Progress At(std::string_view phase, int run_id, std::uint64_t samples = 0) {
  Progress p;
  p.run = run_id;
  p.run_count = 2;
  p.run_id = run_id;
  p.omega_rad_s = 0.5 * run_id;
  p.phase = phase;
  p.samples = samples;
  p.samples_expected = 1000;
  return p;
}

TEST(SessionEvents, PhaseOnEveryChangeProgressAtABoundedRate) {
  Capture capture;
  SessionEventOptions options;
  options.min_progress_period_s = 3600.0;  // within a phase: never again in this test
  SessionEventPublisher publisher(capture.stream(), options);
  RunnerOptions runner;
  publisher.Attach(runner);
  for (const char* phase : {"table", "excite", "ready", "release", "capture"})
    runner.on_progress(At(phase, 1));
  for (int i = 0; i < 50; ++i) runner.on_progress(At("capture", 1, 10u * static_cast<unsigned>(i)));
  runner.on_progress(At("stop", 1, 1000));
  runner.on_progress(At("table", 2));
  const std::vector<nlohmann::json> events = capture.Events();
  std::vector<std::string> phases;
  for (const nlohmann::json& e : OfType(events, "phase")) phases.push_back(e["phase"]);
  EXPECT_EQ(phases, (std::vector<std::string>{"settle", "excite", "ready", "release", "capture",
                                              "stop", "settle"}));
  // One progress event per phase change, none for the 50 reports inside the capture.
  const std::vector<nlohmann::json> progress = OfType(events, "progress");
  ASSERT_EQ(progress.size(), 7u);
  EXPECT_EQ(progress[5]["phase"], "stop");
  EXPECT_EQ(progress[5]["samples"], 1000);
  EXPECT_EQ(progress[5]["run_count"], 2);
  EXPECT_TRUE(progress[5]["table_rate_rad_s"].is_null());  // NaN: not measured
  EXPECT_EQ(progress[6]["run_id"], 2);
  EXPECT_DOUBLE_EQ(progress[6]["omega_rad_s"].get<double>(), 1.0);
}

TEST(SessionEvents, SamplesDecimatedToThePlotsPointsAndNoneLostAtRunEnd) {
  Capture capture;
  SessionEventOptions options;
  options.plot_points_per_run = 100;
  SessionEventPublisher publisher(capture.stream(), options);
  BenchConfigs configs;
  SequenceRun run;
  run.free_run_s = 10.0;
  run.sample_rate_hz = 100;  // 1000 samples: stride 10
  configs.sequence.runs = {run};
  publisher.SessionStarted(configs, "SN1", "sessions/SN1", false, "test");
  RunnerOptions runner;
  publisher.Attach(runner);
  runner.on_progress(At("capture", 1));
  std::vector<GyroSampleRecord> batch(7);  // batches that do not divide the stride
  std::uint32_t seq = 0;
  while (seq < 1000) {
    std::size_t n = 0;
    for (; n < batch.size() && seq < 1000; ++n, ++seq) {
      batch[n].seq = seq;
      batch[n].t_s = 0.01 * seq;
      batch[n].y[0] = seq;
      batch[n].y[3] = -static_cast<double>(seq);
    }
    runner.on_samples(1, std::span(batch.data(), n));
  }
  runner.on_run_end(1, RunEnd{}, 1000);
  const std::vector<nlohmann::json> events = capture.Events();
  std::vector<double> y1;
  for (const nlohmann::json& e : OfType(events, "samples")) {
    EXPECT_EQ(e["run_id"], 1);
    EXPECT_EQ(e["stride"], 10);
    ASSERT_EQ(e["t_s"].size(), e["y"].size());
    for (const nlohmann::json& y : e["y"]) {
      ASSERT_EQ(y.size(), 4u);
      y1.push_back(y[0]);
      EXPECT_EQ(y[3].get<double>(), -y[0].get<double>());
    }
  }
  ASSERT_EQ(y1.size(), 100u);  // every 10th of 1000, the tail flushed before the run's result
  for (std::size_t i = 0; i < y1.size(); ++i) EXPECT_EQ(y1[i], 10.0 * static_cast<double>(i));
  const std::vector<nlohmann::json> results = OfType(events, "run_result");
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0]["samples"], 1000);
  EXPECT_EQ(results[0]["samples_expected"], 1000);
  EXPECT_EQ(results[0]["status"], "complete");
  EXPECT_TRUE(OfType(events, "warning").empty());
  // The session_started event carries the plan.
  const std::vector<nlohmann::json> started = OfType(events, "session_started");
  ASSERT_EQ(started.size(), 1u);
  EXPECT_EQ(started[0]["unit"], "SN1");
  EXPECT_EQ(started[0]["plan"][0]["samples"], 1000);
}

TEST(SessionEvents, AFlaggedRunIsAWarning) {
  Capture capture;
  SessionEventPublisher publisher(capture.stream());
  RunnerOptions runner;
  publisher.Attach(runner);
  RunEnd end;
  end.reason = "flagged: temperature changed by 2 %";
  runner.on_run_end(3, end, 10);
  RunEnd aborted;
  aborted.status = kRunAborted;
  aborted.reason = "aborted by operator during run 4";
  runner.on_run_end(4, aborted, 5);
  const std::vector<nlohmann::json> warnings = OfType(capture.Events(), "warning");
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0]["message"], "run 3 complete: flagged: temperature changed by 2 %");
  EXPECT_EQ(warnings[1]["message"], "run 4 aborted: aborted by operator during run 4");
}

TEST(SessionEvents, TheEndOfASessionInOrder) {
  Capture capture;
  SessionEventPublisher publisher(capture.stream());
  SessionResult result;
  result.outcome = OutcomeKind::kFail;
  result.reason = "out of limits: delta2";
  result.exit_code = kExitFail;
  result.complete_runs = 3;
  result.dir = "sessions/SN1";
  result.warnings = {"weakly determined"};
  result.estimate_json = {{"method", "ml"}};
  Verdict verdict;
  verdict.overall = LimitStatus::kFail;
  LimitResult pass;
  pass.quantity = LimitedQuantity::kDelta1;
  pass.status = LimitStatus::kPass;
  LimitResult fail;
  fail.quantity = LimitedQuantity::kDelta2;
  fail.status = LimitStatus::kFail;
  verdict.results = {pass, fail};
  result.verdict = verdict;
  publisher.SessionFinished(result);
  publisher.ReportWritten("");
  const std::vector<nlohmann::json> events = capture.Events();
  std::vector<std::string> types;
  for (const nlohmann::json& e : events) types.push_back(e["type"]);
  EXPECT_EQ(types, (std::vector<std::string>{"warning", "estimate", "limit", "limit", "outcome",
                                             "report", "end"}));
  EXPECT_EQ(events[1]["estimate"]["method"], "ml");
  EXPECT_EQ(events[3]["status"], "FAIL");
  EXPECT_EQ(events[4]["outcome"], "FAIL");
  EXPECT_EQ(events[4]["exit_code"], kExitFail);
  EXPECT_EQ(events[4]["failed_limits"], nlohmann::json::array({events[3]["quantity"]}));
  EXPECT_TRUE(events[5]["path"].is_null());
}

}  // namespace
}  // namespace hrgbench::bench

namespace hrgbench::bench {
namespace {

// Issue 26 §1: after a stop every reading of the table's rate is an event (the page shows it reach
// zero), however soon after the last one; other progress stays bounded.
TEST(SessionEvents, EveryTableReadingWhileStoppingIsPublished) {
  Capture capture;
  SessionEventOptions options;
  options.min_progress_period_s = 3600.0;
  SessionEventPublisher publisher(capture.stream(), options);
  RunnerOptions runner;
  publisher.Attach(runner);
  runner.on_progress(At("capture", 1, 10));
  for (int i = 0; i < 5; ++i) {
    Progress p = At("stopping", 0);
    p.table_rate_rad_s = -0.1 * (4 - i) / 4.0;
    runner.on_progress(p);
  }
  const std::vector<nlohmann::json> stopping = [&] {
    std::vector<nlohmann::json> out;
    for (const nlohmann::json& e : OfType(capture.Events(), "progress"))
      if (e["phase"] == "stopping") out.push_back(e);
    return out;
  }();
  ASSERT_EQ(stopping.size(), 5u);
  EXPECT_DOUBLE_EQ(stopping.back()["table_rate_rad_s"].get<double>(), 0.0);
}

// A fixture's stream: its units, each unit's run results by position, each unit's outcome with its
// report, the fixture's outcome; no samples (the plot is one unit's).
TEST(SessionEvents, AFixturesUnitsRunsAndOutcomes) {
  Capture capture;
  SessionEventPublisher publisher(capture.stream());
  RunnerOptions runner;
  const nlohmann::json units = {{{"position", "A"}, {"serial", "SN-A"}, {"session", "A-SN-A"}},
                                {{"position", "B"}, {"serial", "SN-B"}, {"session", "B-SN-B"}}};
  publisher.FixtureStarted(units);
  publisher.AttachFixture(runner, units);
  EXPECT_FALSE(runner.on_samples);
  ASSERT_TRUE(runner.on_unit_run_end);
  RunEnd end;
  end.status = kRunComplete;
  end.omega_rad_s = 0.5;
  runner.on_unit_run_end(1, 1, end, 400);
  SessionResult a;
  a.outcome = OutcomeKind::kPass;
  a.exit_code = 0;
  a.reason = "ok";
  SessionResult b;
  b.outcome = OutcomeKind::kFail;
  b.exit_code = 1;
  b.reason = "delta1 out";
  publisher.UnitFinished(0, a, "fx/A-SN-A/report/report.html");
  publisher.UnitFinished(1, b, "");
  publisher.FixtureFinished(OutcomeKind::kFail, 1, "2 units: A PASS, B FAIL", "fx");
  const std::vector<nlohmann::json> events = capture.Events();
  ASSERT_EQ(OfType(events, "fixture_started").size(), 1u);
  const auto runs = OfType(events, "unit_run_result");
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0]["position"], "B");
  EXPECT_EQ(runs[0]["run_id"], 1);
  EXPECT_EQ(runs[0]["status"], "complete");
  const auto outcomes = OfType(events, "unit_outcome");
  ASSERT_EQ(outcomes.size(), 2u);
  EXPECT_EQ(outcomes[0]["outcome"], "PASS");
  EXPECT_EQ(outcomes[0]["report"], "fx/A-SN-A/report/report.html");
  EXPECT_EQ(outcomes[1]["position"], "B");
  EXPECT_TRUE(outcomes[1]["report"].is_null());
  const auto fixture = OfType(events, "outcome");
  ASSERT_EQ(fixture.size(), 1u);
  EXPECT_EQ(fixture[0]["outcome"], "FAIL");
  EXPECT_EQ(fixture[0]["exit_code"], 1);
  EXPECT_TRUE(OfType(events, "samples").empty());
}

// An operator prompt on the stream (issue 26 §1): opened with its text and its picture as a
// data: URI (base64 as RFC 4648 says: "Man" is "TWFu", padding for the rest), then answered.
TEST(SessionEvents, APromptIsAnnouncedWithItsPictureThenItsAnswer) {
  Capture capture;
  SessionEventPublisher publisher(capture.stream());
  RunnerOptions runner;
  publisher.Attach(runner);
  const std::filesystem::path picture =
      std::filesystem::temp_directory_path() / ("prompt-" + std::to_string(::getpid()) + ".png");
  std::ofstream(picture, std::ios::binary) << "Man"
                                           << "Ma";
  const PromptRequest request{"mount", "start", "Mount the unit.", picture, "abc"};
  runner.on_prompt(request, nullptr);
  const PromptReply reply{true, "OP-3", "panel"};
  runner.on_prompt(request, &reply);
  std::filesystem::remove(picture);
  runner.on_prompt({"remove", "end", "Take it off.", "", ""}, nullptr);
  const std::vector<nlohmann::json> events = capture.Events();
  const auto open = OfType(events, "prompt");
  ASSERT_EQ(open.size(), 2u);
  EXPECT_EQ(open[0]["id"], "mount");
  EXPECT_EQ(open[0]["at"], "start");
  EXPECT_EQ(open[0]["text"], "Mount the unit.");
  EXPECT_EQ(open[0]["image"], "data:image/png;base64,TWFuTWE=");
  EXPECT_TRUE(open[1]["image"].is_null());
  const auto answered = OfType(events, "prompt_answered");
  ASSERT_EQ(answered.size(), 1u);
  EXPECT_EQ(answered[0]["id"], "mount");
  EXPECT_EQ(answered[0]["answer"], "confirm");
  EXPECT_EQ(answered[0]["by"], "OP-3");
  EXPECT_EQ(answered[0]["how"], "panel");
}

TEST(SessionEvents, AUnitDecidedEarlyIsAnnouncedWithWhyAndItsInterimK) {
  Capture capture;
  SessionEventPublisher publisher(capture.stream());
  RunnerOptions runner;
  publisher.AttachFixture(runner, nlohmann::json::array({{{"position", "A"}, {"serial", "SN-A"}},
                                                         {{"position", "B"}, {"serial", "SN-B"}}}));
  runner.on_decided(1, EarlyEnd{2, 12, "every limit decided", 2.837});
  const auto decided = OfType(capture.Events(), "decided");
  ASSERT_EQ(decided.size(), 1u);  // once, though a fixture's publisher wraps the unit callbacks
  EXPECT_EQ(decided[0]["unit"], 1);
  EXPECT_EQ(decided[0]["position"], "B");
  EXPECT_EQ(decided[0]["serial"], "SN-B");
  EXPECT_EQ(decided[0]["after_run"], 2);
  EXPECT_EQ(decided[0]["planned_runs"], 12);
  EXPECT_EQ(decided[0]["why"], "every limit decided");
  EXPECT_EQ(decided[0]["interim_coverage_factor"], 2.837);
}

}  // namespace
}  // namespace hrgbench::bench
