// Several units on one table (station-sim-fixture.toml: four simulated units, each on its own
// in-process bus, each with its own truth): the table is sequenced once for all of them, each unit
// gets its own record, estimate and verdict; a unit's own fault ends only its session, a table
// fault or an interrupt every unit's, each record saying why.
//
// The truths below are the numbers written in station-sim-fixture.toml, not read back through the
// loader or the simulator: a unit estimated against another position's truth fails. Tolerance: 4
// reported standard deviations per parameter (as session_end_to_end_test.cpp: the estimator's std
// is checked against Monte Carlo in tests/unit/estimator/statistics_test.cpp).
#include <array>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "bench_test_support.hpp"
#include "hrgbench/session/session.hpp"
#include "sim/in_process_rate_table.hpp"

namespace hrgbench::testing {
namespace {

struct Truth {
  const char* position;
  const char* bus;
  int node;
  std::array<double, 6> delta;
  std::array<double, 4> xi;
};

// station-sim-fixture.toml, position by position (A: [simulated]'s own). C and D share a bus.
constexpr std::array<Truth, 4> kTruths{{
    {"A", "vsim-A", 0, {-0.001, 0.3, 0.0, 0.0, 0.0, 0.0}, {0.01, 0.0, 0.0, 0.0}},
    {"B", "vsim-B", 0, {-0.0008, 0.29, 3e-5, -2e-5, 2e-4, -1e-4}, {-0.005, 0.003, 0.002, -0.004}},
    {"C", "vsim-CD", 1, {-0.0012, 0.31, -4e-5, 1e-5, -3e-4, 2e-4}, {0.008, -0.002, -0.003, 0.001}},
    {"D", "vsim-CD", 2, {-0.0015, 0.305, 2e-5, 4e-5, 1e-4, 3e-4}, {0.0, 0.006, -0.001, 0.005}},
}};

// The node ids of the frames in a unit's candump log (an identifier's last hex digit, gyro CAN
// protocol v2: message | node), with how many frames each.
std::map<int, int> NodesInLog(const std::filesystem::path& dir) {
  std::ifstream in(dir / "can" / "session.log");
  std::map<int, int> nodes;
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t hash = line.find('#');
    if (hash == std::string::npos || hash == 0) continue;
    nodes[std::stoi(line.substr(hash - 1, 1), nullptr, 16)]++;
  }
  return nodes;
}

// The paper's sequence, shortened (2 s runs, a 1 s warm-up window) so each fault test is quick.
void Shorten(bench::BenchConfigs& c) {
  for (bench::SequenceRun& run : c.sequence.runs) run.free_run_s = 2.0;
  c.sequence.warmup.window_s = 1.0;
  c.sequence.timeouts.settle_s = 5.0;
  c.sequence.timeouts.excite_s = 2.0;
}

const drivers::sim_station::InProcessRateTable& Table(const FixtureRun& run) {
  return dynamic_cast<const drivers::sim_station::InProcessRateTable&>(
      *run.station->hardware().table);
}

nlohmann::json Document(const std::filesystem::path& dir) {
  session::ReadOptions read;
  read.load_samples = false;
  auto session = session::ReadSession(dir, read);
  EXPECT_TRUE(session) << (session ? "" : session.error().ToString());
  return session ? session->document : nlohmann::json();
}

// The statuses of the runs in the unit's record, in plan order.
std::vector<std::string> RunStatuses(const std::filesystem::path& dir) {
  std::vector<std::string> statuses;
  const nlohmann::json doc = Document(dir);
  for (const nlohmann::json& run : doc.at("runs"))
    statuses.push_back(run.at("status").get<std::string>());
  return statuses;
}

TEST(BenchFixture, FourUnitsEachFindTheirOwnTruth) {
  // The production sequence (6 runs at ±0.1, ±0.3, ±1 rad/s, 100 s at 1 kHz) once for all four.
  const FixtureRun run =
      RunFixtureOnSimulatedStation("sequence-production.toml", "limits-example.toml");
  ASSERT_EQ(run.results.size(), 4u);
  for (std::size_t u = 0; u < 4; ++u) {
    const bench::SessionResult& result = run.results[u];
    SCOPED_TRACE(kTruths[u].position);
    EXPECT_EQ(result.outcome, bench::OutcomeKind::kPass) << result.reason;
    EXPECT_EQ(result.complete_runs, 6);
    ASSERT_TRUE(result.estimate.has_value()) << result.reason;
    const estimator::EstimateSummary& s = *result.estimate;
    for (int j = 0; j < 6; ++j)
      EXPECT_NEAR(s.delta[j], kTruths[u].delta[static_cast<std::size_t>(j)], 4 * s.delta_std[j])
          << "delta" << j + 1;
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(s.xi[k], kTruths[u].xi[static_cast<std::size_t>(k)], 4 * s.xi_std[k])
          << "xi" << k + 1;
    // Each unit's record: its own serial and bus, its position and the units beside it.
    const nlohmann::json doc = Document(result.dir);
    EXPECT_EQ(doc.at("unit").at("serial"), std::string("FX-") + kTruths[u].position);
    EXPECT_EQ(doc.at("can_log").at("interface"), kTruths[u].bus);
    EXPECT_EQ(doc.at("can_log").at("node"), kTruths[u].node);
    EXPECT_EQ(doc.at("can_log").at("protocol"), 2);
    // Its log is its own node's traffic, also for C and D on one bus.
    const std::map<int, int> nodes = NodesInLog(result.dir);
    ASSERT_EQ(nodes.size(), 1u);
    EXPECT_EQ(nodes.begin()->first, kTruths[u].node);
    EXPECT_GT(nodes.begin()->second, 1'200'000);  // 6 runs × 100 s × 2 frames at 1 kHz
    EXPECT_EQ(doc.at("simulation").at("seed"), 12345u + 1000u * u);
    // Every run of every unit at the same table rate: one table, sequenced once.
    for (std::size_t r = 0; r < 6; ++r)
      EXPECT_EQ(doc.at("runs").at(r).at("end").at("omega_rad_s"),
                Document(run.results[0].dir).at("runs").at(r).at("end").at("omega_rad_s"));
  }
  // The units are told apart: unit B's estimate of δ5 is far outside unit A's truth.
  EXPECT_GT(std::abs(run.results[1].estimate->delta[4] - kTruths[0].delta[4]),
            20 * run.results[1].estimate->delta_std[4]);
  for (const auto& dir : run.dirs) std::filesystem::remove_all(dir.parent_path());
}

TEST(BenchFixture, OneUnitStallsInRunThreeTheOthersGoOn) {
  const FixtureRun run = RunFixtureOnSimulatedStation("sequence-paper.toml", "", [](auto& c) {
    Shorten(c);
    c.station.fixture[1].simulated.gyro_stall_after_samples = 50;
    c.station.fixture[1].simulated.gyro_stall_from_run = 3;
  });
  ASSERT_EQ(run.results.size(), 4u);
  // B: ERROR, its own fault, in run 3; runs 1 and 2 kept, run 3 closed as aborted, 4-5 not run.
  const bench::SessionResult& b = run.results[1];
  EXPECT_EQ(b.outcome, bench::OutcomeKind::kError);
  EXPECT_NE(b.reason.find("capture of run 3 ended: stalled"), std::string::npos) << b.reason;
  EXPECT_EQ(RunStatuses(b.dir),
            (std::vector<std::string>{"complete", "complete", "aborted", "planned", "planned"}));
  const nlohmann::json b_doc = Document(b.dir);
  EXPECT_EQ(b_doc.at("state"), "closed");
  EXPECT_EQ(b_doc.at("outcome").at("reason"), b.reason);
  // The others: every run, estimated and within their model (no limits: PASS on the fit alone).
  for (std::size_t u : {0u, 2u, 3u}) {
    SCOPED_TRACE(kTruths[u].position);
    EXPECT_EQ(run.results[u].outcome, bench::OutcomeKind::kPass) << run.results[u].reason;
    EXPECT_EQ(run.results[u].complete_runs, 5);
    EXPECT_EQ(RunStatuses(run.results[u].dir), std::vector<std::string>(5, "complete"));
  }
  // The table went on after B stopped, and was brought to rest at the end, not safe-stopped.
  EXPECT_FALSE(Table(run).last_command().safe_stop);
  EXPECT_EQ(Table(run).last_command().rate_rad_s, 0.0);
  for (const auto& dir : run.dirs) std::filesystem::remove_all(dir.parent_path());
}

TEST(BenchFixture, UnitNeverReadyEndsOnlyItsSession) {
  const FixtureRun run = RunFixtureOnSimulatedStation("sequence-paper.toml", "", [](auto& c) {
    Shorten(c);
    c.station.fixture[3].simulated.gyro_never_ready = true;
  });
  ASSERT_EQ(run.results.size(), 4u);
  EXPECT_EQ(run.results[3].outcome, bench::OutcomeKind::kError);
  EXPECT_NE(run.results[3].reason.find("gyro not ready within 2 s"), std::string::npos)
      << run.results[3].reason;
  EXPECT_EQ(RunStatuses(run.results[3].dir), std::vector<std::string>(5, "planned"));
  for (std::size_t u : {0u, 1u, 2u})
    EXPECT_EQ(run.results[u].outcome, bench::OutcomeKind::kPass) << run.results[u].reason;
  for (const auto& dir : run.dirs) std::filesystem::remove_all(dir.parent_path());
}

// C's electronics short the bus it shares with D in run 1 (a bus fault on a shared bus): both
// units lose the bus and end as ERROR, each record saying bus-off; A and B, on buses of their own,
// go through every run.
TEST(BenchFixture, ABusFaultOnASharedBusStopsEveryUnitOnIt) {
  const FixtureRun run = RunFixtureOnSimulatedStation("sequence-paper.toml", "", [](auto& c) {
    Shorten(c);
    c.station.fixture[2].simulated.gyro_bus_off_after_samples = 100;
  });
  ASSERT_EQ(run.results.size(), 4u);
  for (std::size_t u : {2u, 3u}) {
    SCOPED_TRACE(kTruths[u].position);
    EXPECT_EQ(run.results[u].outcome, bench::OutcomeKind::kError);
    EXPECT_NE(run.results[u].reason.find("bus-off"), std::string::npos) << run.results[u].reason;
    EXPECT_EQ(run.results[u].complete_runs, 0);
    EXPECT_EQ(Document(run.results[u].dir).at("outcome").at("reason"), run.results[u].reason);
  }
  for (std::size_t u : {0u, 1u}) {
    SCOPED_TRACE(kTruths[u].position);
    EXPECT_EQ(run.results[u].outcome, bench::OutcomeKind::kPass) << run.results[u].reason;
    EXPECT_EQ(run.results[u].complete_runs, 5);
  }
  for (const auto& dir : run.dirs) std::filesystem::remove_all(dir.parent_path());
}

// Position C mounted upside down: it senses −Ω and the Earth rate on −axis. Its record is in its
// own frame (the plan's Ω, the measured Ω and the Earth rate all of the opposite sign to A's), and
// its estimate finds its own truth; given the table's Ω instead, the fit would not be in its model.
TEST(BenchFixture, AnInvertedUnitIsRecordedAndEstimatedInItsOwnFrame) {
  const FixtureRun run = RunFixtureOnSimulatedStation("sequence-paper.toml", "", [](auto& c) {
    Shorten(c);
    c.station.fixture[2].inverted = true;
  });
  ASSERT_EQ(run.results.size(), 4u);
  const bench::SessionResult& c = run.results[2];
  EXPECT_EQ(c.outcome, bench::OutcomeKind::kPass) << c.reason;
  ASSERT_TRUE(c.estimate.has_value()) << c.reason;
  for (int j = 0; j < 6; ++j)
    EXPECT_NEAR(c.estimate->delta[j], kTruths[2].delta[static_cast<std::size_t>(j)],
                4 * c.estimate->delta_std[j])
        << "delta" << j + 1;
  const nlohmann::json a_doc = Document(run.results[0].dir);
  const nlohmann::json c_doc = Document(c.dir);
  for (std::size_t r = 0; r < 5; ++r) {
    const nlohmann::json& a_run = a_doc.at("runs").at(r);
    const nlohmann::json& c_run = c_doc.at("runs").at(r);
    EXPECT_EQ(c_run.at("plan").at("commanded_omega_rad_s").get<double>(),
              -a_run.at("plan").at("commanded_omega_rad_s").get<double>());
    EXPECT_EQ(c_run.at("end").at("omega_rad_s").get<double>(),
              -a_run.at("end").at("omega_rad_s").get<double>());
    EXPECT_EQ(c_run.at("start").at("earth_rate_rad_s").get<double>(),
              -a_run.at("start").at("earth_rate_rad_s").get<double>());
    EXPECT_NE(a_run.at("start").at("earth_rate_rad_s").get<double>(), 0.0);
  }
  for (std::size_t u : {0u, 1u, 3u})
    EXPECT_EQ(run.results[u].outcome, bench::OutcomeKind::kPass) << run.results[u].reason;
  for (const auto& dir : run.dirs) std::filesystem::remove_all(dir.parent_path());
}

// A fault of what the units share stops every unit, safely, each record saying why.
void ExpectEveryUnitStopped(const FixtureRun& run, bench::OutcomeKind outcome,
                            const std::string& reason_contains) {
  ASSERT_EQ(run.results.size(), 4u);
  const std::string& reason = run.results[0].reason;
  EXPECT_NE(reason.find(reason_contains), std::string::npos) << reason;
  for (std::size_t u = 0; u < 4; ++u) {
    SCOPED_TRACE(kTruths[u].position);
    EXPECT_EQ(run.results[u].outcome, outcome);
    EXPECT_EQ(run.results[u].reason, reason);
    const nlohmann::json doc = Document(run.results[u].dir);
    EXPECT_EQ(doc.at("state"), "closed");
    EXPECT_EQ(doc.at("outcome").at("reason"), reason);
    // The run under way is closed as aborted in every unit's record, the ones before kept.
    const std::vector<std::string> statuses = RunStatuses(run.results[u].dir);
    EXPECT_EQ(statuses.front(), "complete");
    EXPECT_EQ(std::count(statuses.begin(), statuses.end(), "aborted"), 1);
  }
  EXPECT_TRUE(Table(run).last_command().safe_stop);
  EXPECT_EQ(Table(run).last_command().rate_rad_s, 0.0);
  for (const auto& dir : run.dirs) std::filesystem::remove_all(dir.parent_path());
}

TEST(BenchFixture, TableFaultStopsEveryUnit) {
  const FixtureRun run = RunFixtureOnSimulatedStation("sequence-paper.toml", "", [](auto& c) {
    Shorten(c);
    c.station.simulated.faults.table_fault_after_s = 9.0;  // after run 1, during run 2 or 3
  });
  ExpectEveryUnitStopped(run, bench::OutcomeKind::kError, "rate table fault during run");
}

TEST(BenchFixture, OperatorInterruptStopsEveryUnit) {
  const FixtureRun run = RunFixtureOnSimulatedStation(
      "sequence-paper.toml", "", Shorten, [](const bench::Progress& p) {
        return p.run == 2 && p.phase == "capture" && p.samples > 80;
      });
  ExpectEveryUnitStopped(run, bench::OutcomeKind::kAborted, "aborted by operator during run 2");
}

}  // namespace
}  // namespace hrgbench::testing
