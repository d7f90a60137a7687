// Issue 27 §1: a session as short as its verdict allows (the sequence's [adaptive]). On the
// simulated station, whose truth is set in its config: a good unit ends once every limit is proven
// conforming, with the estimate still agreeing with the truth; a unit proven out of a limit ends
// early as a FAIL naming it; a unit whose fit is outside the model (the carrier station's
// tracking reference without its report) never ends early: it runs its whole plan and is flagged.
// On a fixture the table makes a run only while a unit on it still needs one.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "bench_test_support.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::testing {
namespace {

void Adaptive(bench::BenchConfigs& configs, int min_runs) {
  configs.sequence.adaptive.stop_when_decided = true;
  configs.sequence.adaptive.min_runs = min_runs;
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
  // Decided at an interim look with the larger k of 4 looks (after runs 2…5) at the file's k = 2
  // (Python's NormalDist: inv_cdf(1 − (1 − cdf(2)) / 4)); closed with the file's k.
  EXPECT_NEAR(outcome.ended_early->interim_coverage_factor, 2.530960494008706, 1e-9);
  for (const bench::LimitResult& limit : run.result.verdict->results)
    EXPECT_EQ(limit.coverage_factor, 2.0) << limit.message;
  // Shorter, not worse: every parameter still within 4 of its reported std of the truth.
  ASSERT_TRUE(run.result.estimate.has_value());
  const nlohmann::json& truth = run.result.estimate_json.at("truth");
  const estimator::EstimateSummary& s = *run.result.estimate;
  for (int j = 0; j < 6; ++j) {
    const double t = truth.at("delta").at(static_cast<std::size_t>(j)).get<double>();
    EXPECT_NEAR(s.delta[j], t, 4 * s.delta_std[j]) << "delta" << j + 1;
  }
  for (int k = 0; k < 4; ++k) {
    if (!s.xi_estimated[static_cast<std::size_t>(k)]) continue;
    const double t = truth.at("xi").at(static_cast<std::size_t>(k)).get<double>();
    EXPECT_NEAR(s.xi[k], t, 4 * s.xi_std[k]) << "xi" << k + 1;
  }
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
  // Announced after the run that decided it, before the session closed; no run after it.
  EXPECT_EQ(runs_when_decided, result.complete_runs);
  EXPECT_EQ(runs_ended, result.complete_runs);
  // The shipped adaptive sequence's 10 interim looks at the example limits' k = 2 (Python's
  // NormalDist: inv_cdf(1 − (1 − cdf(2)) / 10)).
  EXPECT_NEAR(decided[0].second.interim_coverage_factor, 2.8372759804564556, 1e-9);
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
