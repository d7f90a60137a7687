// The typed session record (session/session_record.hpp) reads back what the recorder wrote, field
// by field, and a damaged field is named once: file, field path, line and value.

#include <gtest/gtest.h>

#include <cmath>
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
using testing::SyntheticSamples;

RunStart StartFor(const PlannedRun& plan) {
  RunStart start;
  start.commanded_omega_rad_s = plan.commanded_omega_rad_s;
  start.measured_omega_rad_s = plan.commanded_omega_rad_s + 1e-5;
  start.earth_rate_rad_s = 5.1e-5;
  start.temperature_c = 25.0;
  start.resonant_frequency_hz = 5012.5 + plan.id;
  start.release_t_ns = 1000 + plan.id;
  return start;
}

RunEnd EndFor(const PlannedRun& plan) {
  RunEnd end;
  end.omega_rad_s = plan.commanded_omega_rad_s + 2e-5;
  end.omega_std_error_rad_s = 3e-7;
  end.omega_readings = 40;
  end.omega_source = "rate";
  end.omega_rate_rad_s = end.omega_rad_s;
  end.omega_rate_std_error_rad_s = 3e-7;
  end.omega_rate_readings = 40;
  end.temperature_start_c = 25.0;
  end.temperature_end_c = 25.01;
  end.frequency_start_hz = 5012.5;
  end.frequency_end_hz = 5012.4;
  end.sequence_gaps = 1;
  end.kernel_drops = 2;
  end.bad_frames = 3;
  return end;
}

// A closed session of three runs (run 2 rejected once, then complete), FAIL with an estimate and a
// verdict as the sequencer records them.
fs::path RecordSession(const ScratchDir& scratch) {
  const fs::path dir = scratch / "session";
  SessionHeader header = SyntheticHeader(3);
  header.simulation = json{{"seed", 7}};
  header.electronics = json{{"output_filter", {{"kind", "none"}}}};
  auto recorder = SessionRecorder::Create(dir, header);
  EXPECT_TRUE(recorder.has_value());
  for (const PlannedRun& plan : header.runs) {
    for (int attempt = 0; attempt < (plan.id == 2 ? 2 : 1); ++attempt) {
      EXPECT_TRUE(recorder->BeginRun(plan.id, StartFor(plan)).has_value());
      const auto samples = SyntheticSamples(plan.id, 100, plan.sample_rate_hz);
      EXPECT_TRUE(recorder->AppendSamples(samples).has_value());
      RunEnd end = EndFor(plan);
      if (plan.id == 2 && attempt == 0) {
        end.status = kRunRejected;
        end.reason = "drift";
      }
      EXPECT_TRUE(recorder->EndRun(end).has_value());
    }
  }
  json estimate{{"method", "ml"},
                {"delta", {1e-3, 2e-3, 3e-3, nullptr, 5e-3, 6e-3}},
                {"delta_std", {1e-5, 2e-5, 3e-5, nullptr, 5e-5, 6e-5}},
                {"xi", {0.01, 0.02, 0.03, 0.04}},
                {"xi_std", {1e-4, 2e-4, 3e-4, 4e-4}},
                {"residual_rms", 1e-4},
                {"warnings", {"w1"}},
                {"engineering",
                 {{"frequency_hz", 5012.5},
                  {"quantities",
                   {{{"name", "tau_s"},
                     {"label", "τ"},
                     {"unit", "s"},
                     {"value", 50.0},
                     {"std", 0.5},
                     {"determined", true},
                     {"note", ""}}}}}},
                {"fit", {{"limits", {{"residual_ratio_max", 1.2}}}}},
                {"fitted_runs",
                 {{{"run", 1},
                   {"initial_state", {1.0, 0.0, 0.5, 0.0}},
                   {"phase_coefficients", {0.1}},
                   {"omega_offset_rad_s", 1e-7}}}}};
  json verdict{{"overall", "FAIL"},
               {"fit_acceptable", true},
               {"fit_checks", json::array()},
               {"limits",
                {{{"quantity", "tau_s"},
                  {"status", "FAIL"},
                  {"value", 50.0},
                  {"std", 0.5},
                  {"min", 60.0},
                  {"max", nullptr},
                  {"message", "below"}}}}};
  SessionOutcome outcome{
      OutcomeKind::kFail,
      "tau_s outside limits",
      {FailedParameter{"tau_s", 50.0, 60.0, std::numeric_limits<double>::infinity()}},
      estimate,
      verdict};
  EXPECT_TRUE(recorder->Close(outcome).has_value());
  return dir;
}

TEST(SessionRecordRead, ReadsBackWhatTheRecorderWrote) {
  ScratchDir scratch("record_read");
  const fs::path dir = RecordSession(scratch);
  auto read = session::ReadSessionRecord(dir);
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  const session::SessionRecord& r = *read;
  const SessionHeader header = SyntheticHeader(3);
  EXPECT_EQ(r.file, dir / "session.json");
  EXPECT_EQ(r.state, "closed");
  EXPECT_EQ(r.unit_serial, header.unit_serial);
  EXPECT_EQ(r.station_name, header.station_name);
  EXPECT_EQ(r.software_version, header.software_version);
  EXPECT_EQ(r.realtime_status, header.realtime_status);
  EXPECT_EQ(r.config_sha256.station_sha256, header.config_sha256.station_sha256);
  EXPECT_EQ(r.config_sha256.limits_sha256, header.config_sha256.limits_sha256);
  ASSERT_TRUE(r.started && r.ended);
  EXPECT_FALSE(r.started->utc.empty());
  EXPECT_TRUE(r.started->monotonic_ns.has_value());
  ASSERT_TRUE(r.can_log.has_value());
  EXPECT_EQ(r.can_log->interface_name, "vcan0");
  EXPECT_EQ(r.simulation, (json{{"seed", 7}}));
  ASSERT_TRUE(r.electronics.output_filter.has_value());
  EXPECT_EQ(r.electronics.output_filter->kind, hrgbench::bench::OutputFilterKind::kNone);
  EXPECT_FALSE(r.electronics.pickoff.has_value());  // the header declared none
  ASSERT_EQ(r.runs.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const session::RunRecord& run = r.runs[i];
    const PlannedRun& plan = header.runs[i];
    EXPECT_EQ(run.id, plan.id);
    EXPECT_EQ(run.status, kRunComplete);
    ASSERT_TRUE(run.plan && run.start && run.end);
    EXPECT_EQ(run.plan->commanded_omega_rad_s, plan.commanded_omega_rad_s);
    EXPECT_EQ(run.plan->free_run_s, plan.free_run_s);
    EXPECT_EQ(run.start->values.resonant_frequency_hz, 5012.5 + plan.id);
    EXPECT_EQ(run.start->values.release_t_ns, 1000 + plan.id);
    const RunEnd expected = EndFor(plan);
    EXPECT_EQ(run.omega_rad_s, expected.omega_rad_s);
    EXPECT_EQ(run.end->values.omega_rad_s, expected.omega_rad_s);
    EXPECT_EQ(run.end->values.omega_std_error_rad_s, 3e-7);
    EXPECT_EQ(run.end->values.omega_source, "rate");
    EXPECT_TRUE(std::isnan(run.end->values.omega_angle_rad_s));  // null: not measured
    EXPECT_EQ(run.end->values.temperature_end_c, 25.01);
    EXPECT_EQ(run.end->values.kernel_drops, 2u);
    EXPECT_EQ(run.end->samples, 100u);
  }
  ASSERT_EQ(r.runs[1].attempts.size(), 1u);
  EXPECT_EQ(r.runs[1].attempts[0].status, kRunRejected);
  ASSERT_TRUE(r.runs[1].attempts[0].end.has_value());
  EXPECT_EQ(r.runs[1].attempts[0].end->values.reason, "drift");

  ASSERT_TRUE(r.outcome.has_value());
  const session::OutcomeRecord& o = *r.outcome;
  EXPECT_EQ(o.kind, OutcomeKind::kFail);
  EXPECT_EQ(o.exit_code, kExitFail);
  EXPECT_EQ(o.reason, "tau_s outside limits");
  ASSERT_EQ(o.failed_parameters.size(), 1u);
  EXPECT_EQ(o.failed_parameters[0].min, 60.0);
  EXPECT_TRUE(std::isinf(o.failed_parameters[0].max));
  ASSERT_TRUE(o.estimate.has_value());
  EXPECT_EQ(o.estimate->method, "ml");
  EXPECT_EQ(o.estimate->delta[2], 3e-3);
  EXPECT_TRUE(std::isnan(o.estimate->delta[3]));
  EXPECT_EQ(o.estimate->xi_std[3], 4e-4);
  EXPECT_EQ(o.estimate->warnings, (std::vector<std::string>{"w1"}));
  ASSERT_EQ(o.estimate->engineering.size(), 1u);
  EXPECT_EQ(o.estimate->engineering[0].unit, "s");
  EXPECT_EQ(o.estimate->engineering[0].std, 0.5);
  EXPECT_EQ(o.estimate->fit_residual_ratio_max, 1.2);
  EXPECT_TRUE(std::isnan(o.estimate->fit_whiteness_z_max));
  ASSERT_EQ(o.estimate->fitted_runs.size(), 1u);
  EXPECT_EQ(o.estimate->fitted_runs[0].initial_state[2], 0.5);
  EXPECT_EQ(o.estimate->fitted_runs[0].phase_coefficients, (std::vector<double>{0.1}));
  EXPECT_EQ(o.estimate->fitted_runs[0].omega_offset_rad_s, 1e-7);
  ASSERT_TRUE(o.verdict.has_value());
  EXPECT_EQ(o.verdict->overall, "FAIL");
  ASSERT_EQ(o.verdict->limits.size(), 1u);
  EXPECT_EQ(o.verdict->limits[0].min, 60.0);
  EXPECT_TRUE(std::isnan(o.verdict->limits[0].max));

  // The document overload reads the same record.
  auto again = session::ReadSessionRecord(r.document, r.file);
  ASSERT_TRUE(again.has_value()) << again.error().ToString();
  EXPECT_EQ(again->runs.size(), 3u);
  EXPECT_EQ(again->outcome->estimate->delta[2], o.estimate->delta[2]);
  EXPECT_EQ(again->runs[1].attempts.size(), 1u);
}

TEST(SessionRecordRead, ADamagedFieldIsNamedByFileFieldLineAndValue) {
  ScratchDir scratch("record_damaged");
  const fs::path dir = RecordSession(scratch);
  json doc;
  {
    std::ifstream in(dir / "session.json");
    doc = json::parse(in);
  }
  doc["runs"][2]["end"]["temperature_end_c"] = "warm";
  {
    std::ofstream out(dir / "session.json");
    out << doc.dump(2) << "\n";
  }
  auto read = session::ReadSessionRecord(dir);
  ASSERT_FALSE(read.has_value());
  const session::SessionError& error = read.error();
  EXPECT_EQ(error.file, dir / "session.json");
  EXPECT_EQ(error.field, "runs[2].end.temperature_end_c");
  EXPECT_GT(error.line, 0u);
  EXPECT_NE(error.message.find("\"warm\""), std::string::npos) << error.message;

  doc["runs"][2]["end"]["temperature_end_c"] = 25.0;
  doc["outcome"]["kind"] = "MAYBE";
  auto from_document = session::ReadSessionRecord(doc, dir / "session.json");
  ASSERT_FALSE(from_document.has_value());
  EXPECT_EQ(from_document.error().field, "outcome.kind");
  EXPECT_NE(from_document.error().message.find("MAYBE"), std::string::npos);
}

TEST(SessionRecordRead, ARunningSessionHasNoOutcome) {
  ScratchDir scratch("record_running");
  const fs::path dir = scratch / "session";
  ASSERT_TRUE(SessionRecorder::Create(dir, SyntheticHeader(2)).has_value());
  auto read = session::ReadSessionRecord(dir);
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  EXPECT_EQ(read->state, "running");
  EXPECT_FALSE(read->Closed());
  EXPECT_FALSE(read->ended.has_value());
  ASSERT_EQ(read->runs.size(), 2u);
  EXPECT_EQ(read->runs[0].status, kRunPlanned);
  EXPECT_FALSE(read->runs[0].end.has_value());
}

// What the report's page reads (html_page.cpp): the uncertainty budgets, the engineering
// source, coverage factor and limitations, each run's fit diagnostics, the simulator's truth and
// hrg-sim's top-level provenance; a damaged one is named by its field path and value.
TEST(SessionRecordRead, ThePageFieldsAreTypedAndADamagedOneIsNamed) {
  ScratchDir scratch("record_page_fields");
  const fs::path dir = RecordSession(scratch);
  json doc;
  {
    std::ifstream in(dir / "session.json");
    doc = json::parse(in);
  }
  json& estimate = doc["outcome"]["estimate"];
  json& engineering = estimate["engineering"];
  engineering["frequency_source"] = "runs' start";
  engineering["coverage_factor"] = 2.0;
  engineering["limitations"] = {"one"};
  engineering["quantities"][0]["budget"] = {
      {{"source", "noise"}, {"type", "A"}, {"standard_uncertainty", 0.4}, {"note", ""}},
      {{"source", "model"}, {"type", "B"}, {"standard_uncertainty", nullptr}, {"note", "n"}}};
  estimate["fit"]["runs"] = {{{"run", 2},
                              {"residual_rms", 1e-4},
                              {"noise_sigma", 1e-4},
                              {"residual_ratio", 1.01},
                              {"whiteness_z", 0.3},
                              {"outliers_removed", 0},
                              {"omega_offset_in_std", nullptr}}};
  doc["simulation"]["delta"] = {1, 2, 3, 4, 5, nullptr};
  doc["spec_sha256"] = "ab12";
  doc["description"] = "a spec";
  auto read = session::ReadSessionRecord(doc, dir / "session.json");
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  EXPECT_TRUE(read->config_sha256.recorded);
  EXPECT_EQ(read->spec_sha256, "ab12");
  EXPECT_EQ(read->description, "a spec");
  ASSERT_TRUE(read->simulation_delta.has_value());
  EXPECT_EQ((*read->simulation_delta)[4], 5.0);
  EXPECT_TRUE(std::isnan((*read->simulation_delta)[5]));
  EXPECT_FALSE(read->simulation_xi.has_value());
  const session::EstimateRecord& e = *read->outcome->estimate;
  EXPECT_TRUE(e.delta_recorded);
  EXPECT_TRUE(e.engineering_recorded);
  EXPECT_EQ(e.engineering_frequency_source, "runs' start");
  EXPECT_EQ(e.engineering_coverage_factor, 2.0);
  EXPECT_EQ(e.engineering_limitations, (std::vector<std::string>{"one"}));
  ASSERT_EQ(e.engineering[0].budget.size(), 2u);
  EXPECT_EQ(e.engineering[0].budget[0].standard_uncertainty, 0.4);
  EXPECT_TRUE(std::isnan(e.engineering[0].budget[1].standard_uncertainty));
  EXPECT_EQ(e.engineering[0].budget[1].type, "B");
  ASSERT_EQ(e.fit_runs.size(), 1u);
  EXPECT_EQ(e.fit_runs[0].run, 2);
  EXPECT_EQ(e.fit_runs[0].outliers_removed, 0.0);
  EXPECT_TRUE(std::isnan(e.fit_runs[0].omega_offset_in_std));

  // hrg-sim's session: no software object, its version top-level.
  doc.erase("software");
  doc.erase("config_sha256");
  doc["software_version"] = "sim-1";
  auto sim = session::ReadSessionRecord(doc, dir / "session.json");
  ASSERT_TRUE(sim.has_value()) << sim.error().ToString();
  EXPECT_EQ(sim->software_version, "sim-1");
  EXPECT_FALSE(sim->config_sha256.recorded);

  engineering["quantities"][0]["budget"][1]["standard_uncertainty"] = "large";
  auto damaged = session::ReadSessionRecord(doc, dir / "session.json");
  ASSERT_FALSE(damaged.has_value());
  EXPECT_EQ(damaged.error().field,
            "outcome.estimate.engineering.quantities[0].budget[1].standard_uncertainty");
  EXPECT_NE(damaged.error().message.find("\"large\""), std::string::npos);

  engineering["quantities"][0]["budget"][1]["standard_uncertainty"] = 0.1;
  estimate["fit"]["runs"][0]["whiteness_z"] = true;
  damaged = session::ReadSessionRecord(doc, dir / "session.json");
  ASSERT_FALSE(damaged.has_value());
  EXPECT_EQ(damaged.error().field, "outcome.estimate.fit.runs[0].whiteness_z");
  EXPECT_NE(damaged.error().message.find("true"), std::string::npos);
}

}  // namespace
}  // namespace hrgbench::bench
