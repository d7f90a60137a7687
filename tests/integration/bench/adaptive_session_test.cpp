// Issue 27 §1: a session as short as its verdict allows (the sequence's [adaptive]). On the
// simulated station, whose truth is set in its config: a good unit ends once every limit is proven
// conforming, with the estimate still agreeing with the truth; a unit proven out of a limit ends
// early as a FAIL naming it; a unit whose fit is outside the model (the carrier station's
// tracking reference without its report) never ends early: it runs its whole plan and is flagged.
// On a fixture the table makes a run only while a unit on it still needs one. With looks within
// runs (the shipped adaptive sequence: every 5 s of a run's capture) a unit decided during a run
// stops capturing there, the run complete with what it holds and the record saying why; the
// table's run ends once no unit on it needs more of it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "bench_test_support.hpp"
#include "hrgbench/analysis/interim_looks.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::testing {
namespace {

// How far above the simulated unit's Bryan factor (0.3)
// TheNextRunIsTheOneTheUndecidedLimitNeedsMost puts its limit: inside the guard band after the runs
// at ±0.1 and ±0.3 rad/s, outside it once one at ±1 rad/s is added.
constexpr double kBryanEdgeAbove = 4e-8;

void Adaptive(bench::BenchConfigs& configs, int min_runs) {
  configs.sequence.adaptive.stop_when_decided = true;
  configs.sequence.adaptive.min_runs = min_runs;
}

// The session's estimate against the simulated station's truth (recorded beside it): every δ and
// estimated ξ within 4 of its reported std.
void ExpectTheTruthWithinFourStd(const bench::SessionResult& result) {
  ASSERT_TRUE(result.estimate.has_value()) << result.reason;
  const nlohmann::json& truth = result.estimate_json.at("truth");
  const estimator::EstimateSummary& s = *result.estimate;
  for (int j = 0; j < 6; ++j) {
    const double t = truth.at("delta").at(static_cast<std::size_t>(j)).get<double>();
    EXPECT_NEAR(s.delta[j], t, 4 * s.delta_std[j]) << "delta" << j + 1;
  }
  for (int k = 0; k < 4; ++k) {
    if (!s.xi_estimated[static_cast<std::size_t>(k)]) continue;
    const double t = truth.at("xi").at(static_cast<std::size_t>(k)).get<double>();
    EXPECT_NEAR(s.xi[k], t, 4 * s.xi_std[k]) << "xi" << k + 1;
  }
}

// The record's outcome as its one typed reader reads it.
session::OutcomeRecord RecordedOutcome(const std::filesystem::path& dir) {
  auto recorded = session::ReadSessionRecord(dir);
  EXPECT_TRUE(recorded) << recorded.error().ToString();
  if (!recorded || !recorded->outcome) return {};
  return *recorded->outcome;
}

TEST(BenchAdaptive, AGoodUnitEndsOnceEveryLimitIsProvenConforming) {
  const BenchRun run = RunOnSimulatedStation("sequence-production.toml", "limits-example.toml",
                                             [](bench::BenchConfigs& c) { Adaptive(c, 2); });
  ASSERT_EQ(run.result.outcome, bench::OutcomeKind::kPass) << run.result.reason;
  ASSERT_TRUE(run.result.verdict.has_value());
  for (const bench::LimitResult& limit : run.result.verdict->results)
    EXPECT_EQ(limit.zone, bench::DecisionZone::kConforming) << limit.message;
  // Fewer runs than the six planned, at least the two asked for.
  EXPECT_GE(run.result.complete_runs, 2);
  EXPECT_LT(run.result.complete_runs, 6);
  const session::OutcomeRecord outcome = RecordedOutcome(run.dir);
  ASSERT_TRUE(outcome.ended_early.has_value());
  EXPECT_EQ(outcome.ended_early->after_run, run.result.complete_runs);
  EXPECT_EQ(outcome.ended_early->planned_runs, 6);
  EXPECT_EQ(outcome.ended_early->why, "every limit decided");
  EXPECT_NE(run.result.reason.find("decided after run"), std::string::npos) << run.result.reason;
  // Decided at an interim look with the k of the plan's 4 looks, after runs 2…5 of six equal runs
  // (interim_looks_test checks that function against Pocock's boundaries and a Monte Carlo);
  // closed with the file's k.
  const std::vector<double> looks = {2.0 / 6, 3.0 / 6, 4.0 / 6, 5.0 / 6};
  EXPECT_NEAR(outcome.ended_early->interim_coverage_factor,
              bench::InterimCoverageFactor(2.0, looks), 1e-9);
  EXPECT_GT(outcome.ended_early->interim_coverage_factor, 2.3);
  EXPECT_FALSE(std::isfinite(outcome.ended_early->within_run_s));
  for (const bench::LimitResult& limit : run.result.verdict->results)
    EXPECT_EQ(limit.coverage_factor, 2.0) << limit.message;
  // Shorter, not worse: every parameter still within 4 of its reported std of the truth.
  ExpectTheTruthWithinFourStd(run.result);
  // The runs not needed are in the record's plan, never begun.
  auto session = session::ReadSession(run.dir);
  ASSERT_TRUE(session) << session.error().ToString();
  EXPECT_EQ(session->loaded_run_ids.size(), static_cast<std::size_t>(run.result.complete_runs));
}

TEST(BenchAdaptive, TheDecisionIsAnnouncedAsItIsTaken) {
  std::unique_ptr<app::Station> station;
  auto configs = OpenShippedStation("station-sim.toml", "sequence-production-adaptive.toml",
                                    "limits-example.toml", {}, station);
  ASSERT_TRUE(configs);
  ConfirmEveryPrompt confirm;
  bench::RunnerOptions options;
  options.unit_serial = "TEST-DECIDED";
  options.software_version = "test";
  options.simulation = station->simulation();
  options.prompts = &confirm;
  std::vector<std::pair<std::size_t, bench::EarlyEnd>> decided;
  int runs_when_decided = -1, runs_ended = 0;
  options.on_run_end = [&](int, const bench::RunEnd&, std::uint64_t) { ++runs_ended; };
  options.on_decided = [&](std::size_t unit, const bench::EarlyEnd& end) {
    decided.emplace_back(unit, end);
    runs_when_decided = runs_ended;
  };
  const std::filesystem::path dir = FreshDir("decided");
  const RemovedAtEnd removes(dir);
  const bench::SessionResult result =
      bench::RunSession(*configs, station->hardware(), dir, options);
  ASSERT_EQ(result.outcome, bench::OutcomeKind::kPass) << result.reason;
  ASSERT_EQ(decided.size(), 1u);
  EXPECT_EQ(decided[0].first, 0u);
  EXPECT_EQ(decided[0].second.after_run, result.complete_runs);
  EXPECT_EQ(decided[0].second.planned_runs, 12);
  // Announced as it was taken: during the run that decided it (before that run's end), or after
  // it; no run after it.
  const bool within = std::isfinite(decided[0].second.within_run_s);
  EXPECT_EQ(runs_when_decided, result.complete_runs - (within ? 1 : 0));
  EXPECT_EQ(runs_ended, result.complete_runs);
  // The shipped adaptive sequence's 82 interim looks at the example limits' k = 2: every 5 s from
  // 20 s to 75 s of each 80 s run (a look within a run waits until it is as long as the shortest
  // run made, 20 s), and after runs 2 … 11 (information as the share of the 600 s of free run).
  std::vector<double> looks;
  double before = 0.0;
  for (int run = 1; run <= 12; ++run) {
    const double length = run <= 6 ? 20.0 : 80.0;
    for (double at = 20.0; run >= 7 && at < length; at += 5.0) looks.push_back((before + at) / 600);
    before += length;
    if (run >= 2 && run < 12) looks.push_back(before / 600);
  }
  ASSERT_EQ(looks.size(), 82u);
  EXPECT_NEAR(decided[0].second.interim_coverage_factor, bench::InterimCoverageFactor(2.0, looks),
              1e-9);
}

// The production sequence with its first run cut to 20 s and looks every 5 s from the second run
// on: the second run's first look is at 20 s (as long as the first run), where a good unit is
// decided.
void LooksWithinRuns(bench::BenchConfigs& c) {
  Adaptive(c, 2);
  c.sequence.adaptive.look_interval_s = 5.0;
  c.sequence.runs.front().free_run_s = 20.0;
}

TEST(BenchAdaptive, AUnitDecidedWithinARunStopsCapturingThereAndTheRecordSaysWhy) {
  const BenchRun run =
      RunOnSimulatedStation("sequence-production.toml", "limits-example.toml", LooksWithinRuns);
  ASSERT_EQ(run.result.outcome, bench::OutcomeKind::kPass) << run.result.reason;
  const session::OutcomeRecord outcome = RecordedOutcome(run.dir);
  ASSERT_TRUE(outcome.ended_early.has_value()) << run.result.reason;
  const bench::EarlyEnd& early = *outcome.ended_early;
  // A good unit far inside its limits: decided at the first look within its second run.
  ASSERT_TRUE(std::isfinite(early.within_run_s)) << run.result.reason;
  EXPECT_EQ(early.after_run, 2);
  EXPECT_GE(early.within_run_s, 20.0);
  EXPECT_LT(early.within_run_s, 21.0);
  EXPECT_EQ(early.why, "every limit decided");
  EXPECT_NE(run.result.reason.find("s into run 2 of 6"), std::string::npos) << run.result.reason;
  auto record = session::ReadSessionRecord(run.dir);
  ASSERT_TRUE(record) << record.error().ToString();
  ASSERT_EQ(record->runs.size(), 6u);
  // Run 2 is complete with what its capture held when it stopped: the samples to the look, and
  // those the capture took before its stop was seen. The look takes no simulated time (its thread
  // holds the clock), its answer comes at the sequencer's next 20 ms loop and the stop within the
  // capture's 10 ms read timeout: well under 100 samples at 1 kHz, on a busy machine as on an idle
  // one.
  const session::RunRecord& second = record->runs[1];
  EXPECT_EQ(second.status, bench::kRunComplete);
  ASSERT_TRUE(second.end.has_value());
  EXPECT_EQ(second.end->values.decided_at_s, early.within_run_s);
  EXPECT_EQ(second.end->values.decided_why, "every limit decided");
  EXPECT_EQ(second.end->values.decided_coverage_factor, early.interim_coverage_factor);
  ASSERT_TRUE(second.end->samples.has_value());
  const auto at_look = static_cast<std::uint64_t>(std::llround(early.within_run_s * 1000.0)) + 1;
  EXPECT_GE(*second.end->samples, at_look);
  EXPECT_LT(*second.end->samples, at_look + 100);
  // Run 1 went its planned length, and says nothing of a decision; runs 3 … 6 never began.
  ASSERT_TRUE(record->runs[0].end.has_value());
  EXPECT_EQ(record->runs[0].end->samples, 20000u);
  EXPECT_FALSE(std::isfinite(record->runs[0].end->values.decided_at_s));
  for (std::size_t r = 2; r < 6; ++r) EXPECT_EQ(record->runs[r].status, bench::kRunPlanned) << r;
  // The session closed with the record's whole runs estimated at the file's k, and it agrees
  // with the simulated truth.
  ASSERT_EQ(run.result.complete_runs, 2);
  ASSERT_TRUE(run.result.verdict.has_value());
  for (const bench::LimitResult& limit : run.result.verdict->results) {
    EXPECT_EQ(limit.coverage_factor, 2.0) << limit.message;
    EXPECT_EQ(limit.zone, bench::DecisionZone::kConforming) << limit.message;
  }
  auto session = session::ReadSession(run.dir);
  ASSERT_TRUE(session) << session.error().ToString();
  ASSERT_EQ(session->loaded_samples.size(), 2u);
  EXPECT_EQ(session->loaded_samples[1].size(), *second.end->samples);
  ExpectTheTruthWithinFourStd(run.result);
}

TEST(BenchAdaptive, AFixtureRunEndsOnceNoUnitOnTheTableNeedsMoreOfIt) {
  const FixtureRun run = RunFixtureOnSimulatedStation("sequence-production.toml",
                                                      "limits-example.toml", LooksWithinRuns);
  ASSERT_EQ(run.results.size(), 4u);
  for (const bench::SessionResult& result : run.results) {
    SCOPED_TRACE(result.dir.filename().string());
    EXPECT_EQ(result.outcome, bench::OutcomeKind::kPass) << result.reason;
    const session::OutcomeRecord outcome = RecordedOutcome(result.dir);
    ASSERT_TRUE(outcome.ended_early.has_value()) << result.reason;
    auto record = session::ReadSessionRecord(result.dir);
    ASSERT_TRUE(record) << record.error().ToString();
    const session::RunRecord& last =
        record->runs[static_cast<std::size_t>(outcome.ended_early->after_run - 1)];
    ASSERT_TRUE(last.end.has_value());
    ASSERT_TRUE(last.end->samples.has_value());
    // Each unit stopped capturing at its own decision, short of the run's 100 000 samples.
    ASSERT_TRUE(std::isfinite(outcome.ended_early->within_run_s)) << result.reason;
    EXPECT_EQ(last.end->values.decided_at_s, outcome.ended_early->within_run_s);
    EXPECT_LT(*last.end->samples, 100000u);
    for (std::size_t r = static_cast<std::size_t>(outcome.ended_early->after_run); r < 6; ++r)
      EXPECT_EQ(record->runs[r].status, bench::kRunPlanned) << "run " << r + 1;
  }
}

// The runs the record made, in the order they were made (their releases' bench-clock stamps).
std::vector<int> RunsInOrderMade(const std::filesystem::path& dir) {
  auto record = session::ReadSessionRecord(dir);
  EXPECT_TRUE(record) << record.error().ToString();
  std::vector<std::pair<std::int64_t, int>> made;
  if (!record) return {};
  for (const session::RunRecord& run : record->runs) {
    if (run.status == bench::kRunComplete && run.start)
      made.emplace_back(run.start->at.monotonic_ns.value_or(0), run.id);
  }
  std::sort(made.begin(), made.end());
  std::vector<int> ids;
  for (const auto& [at, id] : made) ids.push_back(id);
  return ids;
}

TEST(BenchAdaptive, TheNextRunIsTheOneTheUndecidedLimitNeedsMost) {
  // The Bryan factor's limits (δ2 and the angular gain) put just above the simulated unit's 0.3:
  // after the two runs at ±0.1 rad/s the value is inside the guard band. The precession tells δ2
  // in proportion to Ω²: a 100 s run at ±1 rad/s tells 11 times what one at ±0.3 rad/s does, at
  // the same table time. So the look after run 2 asks for run 5 or 6 (±1 rad/s) before run 3.
  const auto edit = [](bench::BenchConfigs& c) {
    Adaptive(c, 2);
    c.sequence.adaptive.most_informative_next = true;
    for (bench::ParameterLimit& limit : c.limits.limits) {
      if (limit.quantity == bench::LimitedQuantity::kDelta2 ||
          limit.quantity == bench::LimitOf(estimator::EngineeringQuantity::kAngularGain))
        limit.max = 0.3 + kBryanEdgeAbove;
    }
  };
  const BenchRun run =
      RunOnSimulatedStation("sequence-production.toml", "limits-example.toml", edit);
  const std::vector<int> made = RunsInOrderMade(run.dir);
  ASSERT_GE(made.size(), 3u) << run.result.reason;
  EXPECT_EQ(made[0], 1);
  EXPECT_EQ(made[1], 2);
  EXPECT_TRUE(made[2] == 5 || made[2] == 6) << "third run made: " << made[2];
  // And the plan's order without it: run 3 third.
  const BenchRun in_order = RunOnSimulatedStation(
      "sequence-production.toml", "limits-example.toml", [&](bench::BenchConfigs& c) {
        edit(c);
        c.sequence.adaptive.most_informative_next = false;
      });
  const std::vector<int> planned = RunsInOrderMade(in_order.dir);
  ASSERT_GE(planned.size(), 3u) << in_order.result.reason;
  EXPECT_EQ(planned[2], 3);
  // Decided sooner for it (here after runs 1, 2, 5 against 1 … 5 in the plan's order: the runs at
  // ±0.3 rad/s do not resolve the edge, one at ±1 rad/s does), never with another verdict.
  EXPECT_LT(made.size(), planned.size());
  EXPECT_EQ(run.result.outcome, in_order.result.outcome)
      << run.result.reason << " / " << in_order.result.reason;
}

TEST(BenchAdaptive, AUnitProvenOutOfALimitEndsEarlyAsAFailNamingIt) {
  // The simulated unit's δ2 is 0.3: limits it is far outside of.
  const BenchRun run = RunOnSimulatedStation(
      "sequence-production.toml", "limits-example.toml", [](bench::BenchConfigs& c) {
        Adaptive(c, 1);
        for (bench::ParameterLimit& limit : c.limits.limits) {
          if (limit.quantity == bench::LimitedQuantity::kDelta2) {
            limit.min = 0.31;
            limit.max = 0.4;
          }
        }
        std::erase_if(c.limits.limits, [](const bench::ParameterLimit& limit) {
          return limit.quantity ==
                 bench::LimitOf(estimator::EngineeringQuantity::kAngularGain);  // δ2 again
        });
      });
  ASSERT_EQ(run.result.outcome, bench::OutcomeKind::kFail) << run.result.reason;
  EXPECT_LT(run.result.complete_runs, 6);
  const session::OutcomeRecord outcome = RecordedOutcome(run.dir);
  ASSERT_TRUE(outcome.ended_early.has_value()) << run.result.reason;
  EXPECT_EQ(outcome.ended_early->why, "delta2 proven non-conforming");
  ASSERT_EQ(outcome.failed_parameters.size(), 1u);
  EXPECT_EQ(outcome.failed_parameters[0].name, "delta2");
}

TEST(BenchAdaptive, AFitOutsideTheModelNeverEndsASessionEarly) {
  const BenchRun run = RunOnSimulatedStation(
      "sequence-production.toml", "limits-example.toml",
      [](bench::BenchConfigs& c) {
        Adaptive(c, 1);
        c.station.simulated.carrier.tracking_reference = true;
        c.station.simulated.carrier.pll_bandwidth_hz = 2.0;
        c.station.simulated.carrier.report_reference_phase = false;
      },
      {}, {}, "station-sim-carrier.toml");
  EXPECT_NE(run.result.outcome, bench::OutcomeKind::kPass) << run.result.reason;
  ASSERT_TRUE(run.result.verdict.has_value()) << run.result.reason;
  EXPECT_FALSE(run.result.verdict->fit_acceptable);
  EXPECT_EQ(run.result.complete_runs, 6);
  EXPECT_FALSE(RecordedOutcome(run.dir).ended_early.has_value());
}

TEST(BenchAdaptive, AFixtureStopsTakingRunsOnceEveryUnitOnItIsDecided) {
  // station-sim-fixture.toml: four good units, each with its own truth and bus.
  const FixtureRun run =
      RunFixtureOnSimulatedStation("sequence-production.toml", "limits-example.toml",
                                   [](bench::BenchConfigs& c) { Adaptive(c, 2); });
  ASSERT_EQ(run.results.size(), 4u);
  int table_runs = 0;  // the runs the table made: the last unit's decision ends them
  for (const bench::SessionResult& result : run.results) {
    SCOPED_TRACE(result.dir.filename().string());
    EXPECT_EQ(result.outcome, bench::OutcomeKind::kPass) << result.reason;
    EXPECT_GE(result.complete_runs, 2);
    EXPECT_LT(result.complete_runs, 6);
    table_runs = std::max(table_runs, result.complete_runs);
    const session::OutcomeRecord outcome = RecordedOutcome(result.dir);
    ASSERT_TRUE(outcome.ended_early.has_value()) << result.reason;
    EXPECT_EQ(outcome.ended_early->after_run, result.complete_runs);
    EXPECT_EQ(outcome.ended_early->planned_runs, 6);
  }
  ASSERT_LT(table_runs, 6);
  // In every unit's record the runs after the last decision are still planned: never begun for
  // anyone (a decided unit is not waited for, and no unit is left that needs them).
  for (const bench::SessionResult& result : run.results) {
    SCOPED_TRACE(result.dir.filename().string());
    session::ReadOptions read;
    read.load_samples = false;
    auto session = session::ReadSession(result.dir, read);
    ASSERT_TRUE(session) << session.error().ToString();
    ASSERT_EQ(session->runs.size(), 6u);
    for (std::size_t r = 0; r < 6; ++r) {
      const bool made = static_cast<int>(r) < result.complete_runs;
      EXPECT_EQ(session->runs[r].status, made ? "complete" : "planned") << "run " << r + 1;
    }
    EXPECT_TRUE(session->warnings.empty()) << session->warnings.front();
  }
  EXPECT_GT(table_runs, 0);
}

}  // namespace
}  // namespace hrgbench::testing
