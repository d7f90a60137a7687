// SessionRecorder on a healthy disk: a full session reads back exactly through the session
// library, files are final at EndRun, session.json is only ever replaced by rename.

#include "hrgbench/session/session_recorder.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <sstream>
#include <thread>

#include "can_frame_assertions.hpp"
#include "candump_log_parser.hpp"
#include "hrgbench/session/session.hpp"
#include "record_test_dir.hpp"
#include "synthetic_gyro_record.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::ScratchDir;
using testing::SyntheticHeader;
using testing::SyntheticSamples;

json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  return json::parse(in);
}

RunStart StartFor(const PlannedRun& plan) {
  RunStart start;
  start.commanded_omega_rad_s = plan.commanded_omega_rad_s;
  start.measured_omega_rad_s = plan.commanded_omega_rad_s + 1e-5;
  start.earth_rate_rad_s = 7.292115e-5 * 0.7;
  start.temperature_c = 25.0;
  start.resonant_frequency_hz = 5012.5;
  start.release_t_ns = 123'456'789 + plan.id;
  start.with_measured_omega = true;
  start.with_temperature = true;
  start.with_resonant_frequency = true;
  return start;
}

RunEnd CompleteEnd(const PlannedRun& plan) {
  RunEnd end;
  end.omega_rad_s = plan.commanded_omega_rad_s + 1e-5 + 7.292115e-5 * 0.7;
  end.temperature_start_c = 25.0;
  end.temperature_end_c = 25.005;
  end.frequency_start_hz = 5012.5;
  end.frequency_end_hz = 5012.49;
  end.sequence_gaps = 1;
  end.kernel_drops = 2;
  end.bad_frames = 3;
  return end;
}

// Records every planned run, in batches of 64 samples.
void RecordRun(SessionRecorder& recorder, const PlannedRun& plan, const RunEnd& end) {
  ASSERT_TRUE(recorder.BeginRun(plan.id, StartFor(plan)).has_value());
  const auto samples =
      SyntheticSamples(plan.id, 500, plan.sample_rate_hz, plan.commanded_omega_rad_s);
  for (std::size_t k = 0; k < samples.size(); k += 64) {
    const std::size_t n = std::min<std::size_t>(64, samples.size() - k);
    auto appended = recorder.AppendSamples(std::span(samples).subspan(k, n));
    ASSERT_TRUE(appended.has_value()) << appended.error().ToString();
  }
  auto ended = recorder.EndRun(end);
  ASSERT_TRUE(ended.has_value()) << ended.error().ToString();
}

TEST(SessionRecorder, FullSessionReadsBackExactlyThroughTheSessionLibrary) {
  ScratchDir scratch("recorder_full");
  const fs::path dir = scratch / "session";
  SessionHeader header = SyntheticHeader(3);
  header.simulation = json{{"seed", 42}, {"delta_tau_s", 1e-3}};
  auto recorder = SessionRecorder::Create(dir, header);
  ASSERT_TRUE(recorder.has_value()) << recorder.error().ToString();

  // Right after Create: a valid session, every run planned, nothing loaded.
  json doc = ReadJson(dir / "session.json");
  EXPECT_EQ(doc["state"], "running");
  EXPECT_EQ(doc["runs"][1]["status"], "planned");
  EXPECT_EQ(doc["runs"][1]["plan"]["commanded_omega_rad_s"], 0.2);
  ASSERT_TRUE(session::ReadSession(dir).has_value());

  std::vector<LoggedCanFrame> frames;
  for (const PlannedRun& plan : header.runs) {
    hw::CanFrame frame;
    frame.id = 0x180 + static_cast<std::uint32_t>(plan.id);
    frame.length = 2;
    frame.data[0] = static_cast<std::uint8_t>(plan.id);
    frames.push_back({1'700'000'000'000'000'000 + plan.id * 1'000'000'000LL, frame});
    ASSERT_TRUE(recorder->AppendCanFrames(std::span(&frames.back(), 1)).has_value());
    RecordRun(*recorder, plan, CompleteEnd(plan));
  }
  EXPECT_EQ(recorder->CompleteRunIds(), (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(recorder->RemainingRunIds().empty());
  SessionOutcome outcome{OutcomeKind::kFail,
                         "delta_tau_s outside limits",
                         {FailedParameter{"delta_tau_s", 2e-3, -1e-3, 1e-3}},
                         json{{"delta_tau_s", 2e-3}},
                         std::nullopt};
  ASSERT_TRUE(recorder->Close(outcome).has_value());
  EXPECT_FALSE(recorder->BeginRun(1, {}).has_value());

  auto read = session::ReadSession(dir);
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  EXPECT_TRUE(read->warnings.empty());
  EXPECT_EQ(read->serial, "HRG-TEST-0001");
  EXPECT_EQ(read->sample_rate_hz, 1000.0);
  ASSERT_EQ(read->loaded_run_ids, (std::vector<int>{1, 2, 3}));
  const auto runs = session::ToRunData(*read);
  for (std::size_t r = 0; r < 3; ++r) {
    const PlannedRun& plan = header.runs[r];
    EXPECT_EQ(runs[r].omega_rad_s, CompleteEnd(plan).omega_rad_s);  // bit-exact
    const auto samples =
        SyntheticSamples(plan.id, 500, plan.sample_rate_hz, plan.commanded_omega_rad_s);
    ASSERT_EQ(runs[r].t_s.size(), samples.size());
    const auto& extra = read->loaded_samples[r].extra_columns;
    for (std::size_t k = 0; k < samples.size(); ++k) {
      ASSERT_EQ(runs[r].t_s[k], samples[k].t_s);
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(runs[r].y(c, static_cast<Eigen::Index>(k)), samples[k].y[c]);
      ASSERT_EQ(extra.at("seq")[k], samples[k].seq);
      ASSERT_EQ(extra.at("omega_meas_rad_s")[k], samples[k].measured_omega_rad_s);
      ASSERT_EQ(extra.at("temp_c")[k], samples[k].temperature_c);
      ASSERT_EQ(extra.at("freq_hz")[k], samples[k].resonant_frequency_hz);
    }
  }
  // The metadata rule 9 asks for.
  doc = read->document;
  EXPECT_EQ(doc["state"], "closed");
  EXPECT_EQ(doc["station"]["name"], "test-station");
  EXPECT_EQ(doc["software"]["version"], "test-build");
  EXPECT_EQ(doc["config_sha256"]["limits"], std::string(64, 'c'));
  EXPECT_EQ(doc["realtime"], header.realtime_status);
  EXPECT_EQ(doc["simulation"]["seed"], 42);
  EXPECT_TRUE(doc["started"]["utc"].get<std::string>().ends_with("Z"));
  EXPECT_TRUE(doc["ended"].contains("monotonic_ns"));
  EXPECT_EQ(doc["outcome"]["kind"], "FAIL");
  EXPECT_EQ(doc["outcome"]["exit_code"], 1);
  EXPECT_EQ(doc["outcome"]["failed_parameters"][0]["name"], "delta_tau_s");
  EXPECT_EQ(doc["outcome"]["estimate"]["delta_tau_s"], 2e-3);
  const json& run2 = doc["runs"][1];
  EXPECT_EQ(run2["start"]["release_t_ns"], 123'456'791);
  EXPECT_EQ(run2["start"]["temperature_c"], 25.0);
  EXPECT_EQ(run2["end"]["kernel_drops"], 2);
  EXPECT_EQ(run2["end"]["samples"], 500);
  EXPECT_EQ(run2["end"]["frequency_end_hz"], 5012.49);
  // No stray temporaries or partial files.
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.find(".tmp."), std::string::npos) << name;
    EXPECT_FALSE(name.ends_with(".partial")) << name;
  }
  // The CAN log holds the frames.
  const auto lines = testing::ReadCandumpLog((dir / "can" / "session.log").string());
  ASSERT_TRUE(lines.has_value());
  ASSERT_EQ(lines->size(), frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ((*lines)[k].interface_name, "vcan0");
    EXPECT_TRUE(testing::SameFrame(frames[k].frame, (*lines)[k].frame));
  }
}

TEST(SessionRecorder, RunDataIsFinalOnDiskAsSoonAsTheRunEnds) {
  ScratchDir scratch("recorder_final");
  const fs::path dir = scratch / "s";
  const SessionHeader header = SyntheticHeader(2);
  RecorderOptions options;
  options.flush_interval_ns = 0;  // write out on every append
  auto recorder = SessionRecorder::Create(dir, header, options);
  ASSERT_TRUE(recorder.has_value());
  ASSERT_TRUE(recorder->BeginRun(1, StartFor(header.runs[0])).has_value());
  EXPECT_EQ(ReadJson(dir / "session.json")["runs"][0]["status"], "running");
  const auto samples = SyntheticSamples(1, 100, 1000.0);
  ASSERT_TRUE(recorder->AppendSamples(samples).has_value());
  // Streamed: the samples are in the .partial before the run ends.
  EXPECT_GT(fs::file_size(dir / "runs" / "run-001.csv.partial"), 100u * 40);
  EXPECT_EQ(recorder->samples_in_open_run(), 100u);
  ASSERT_TRUE(recorder->EndRun(CompleteEnd(header.runs[0])).has_value());
  // Final without Close: the estimator can read run 1 now.
  auto read = session::ReadSession(dir);
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  EXPECT_EQ(read->loaded_run_ids, std::vector<int>{1});
  EXPECT_EQ(read->document["state"], "running");
  EXPECT_FALSE(fs::exists(dir / "runs" / "run-001.csv.partial"));
}

TEST(SessionRecorder, ARejectedRunIsSkippedByTheEstimatorAndKeptAsAnAttemptWhenRunAgain) {
  ScratchDir scratch("recorder_rejected");
  const fs::path dir = scratch / "s";
  const SessionHeader header = SyntheticHeader(2);
  auto recorder = SessionRecorder::Create(dir, header);
  ASSERT_TRUE(recorder.has_value());
  RunEnd rejected = CompleteEnd(header.runs[0]);
  rejected.status = kRunRejected;
  rejected.reason = "temperature drift 1.4 % > 1 %";
  RecordRun(*recorder, header.runs[0], rejected);
  auto read = session::ReadSession(dir);
  ASSERT_TRUE(read.has_value());
  EXPECT_TRUE(read->loaded_run_ids.empty());
  EXPECT_EQ(recorder->RemainingRunIds(), (std::vector<int>{1, 2}));

  RecordRun(*recorder, header.runs[0], CompleteEnd(header.runs[0]));
  EXPECT_TRUE(fs::exists(dir / "runs" / "run-001.csv.attempt-1"));
  const json doc = ReadJson(dir / "session.json");
  EXPECT_EQ(doc["runs"][0]["status"], "complete");
  EXPECT_EQ(doc["runs"][0]["attempts"][0]["status"], "rejected");
  EXPECT_EQ(doc["runs"][0]["attempts"][0]["end"]["reason"], rejected.reason);
  EXPECT_EQ(doc["runs"][0]["attempts"][0]["file"], "runs/run-001.csv.attempt-1");
  EXPECT_EQ(recorder->Runs()[0].attempts, 1);
  // A complete run is not run again.
  EXPECT_EQ(recorder->BeginRun(1, {}).error().kind, RecordErrorKind::kWrongState);
}

TEST(SessionRecorder, CloseEndsAnOpenRunAsAborted) {
  ScratchDir scratch("recorder_abort");
  const fs::path dir = scratch / "s";
  const SessionHeader header = SyntheticHeader(2);
  auto recorder = SessionRecorder::Create(dir, header);
  ASSERT_TRUE(recorder.has_value());
  ASSERT_TRUE(recorder->BeginRun(1, StartFor(header.runs[0])).has_value());
  ASSERT_TRUE(recorder->AppendSamples(SyntheticSamples(1, 10, 1000.0)).has_value());
  ASSERT_TRUE(
      recorder->Close({OutcomeKind::kAborted, "operator pressed Ctrl-C", {}, {}, {}}).has_value());
  const json doc = ReadJson(dir / "session.json");
  EXPECT_EQ(doc["runs"][0]["status"], "aborted");
  EXPECT_EQ(doc["runs"][0]["omega_rad_s"], 0.1);  // commanded: no measured Ω was given
  EXPECT_EQ(doc["runs"][0]["end"]["reason"], "session closed: operator pressed Ctrl-C");
  EXPECT_EQ(doc["outcome"]["kind"], "ABORTED");
  EXPECT_EQ(doc["outcome"]["exit_code"], 3);
  auto samples = session::ReadRunCsv(dir / "runs" / "run-001.csv");
  ASSERT_TRUE(samples.has_value());
  EXPECT_EQ(samples->size(), 10u);
}

// session.json is replaced by rename (a new inode every write), never rewritten in place, and a
// reader polling it while the recorder works always finds a whole, parseable file.
TEST(SessionRecorder, SessionJsonIsNeverHalfWritten) {
  ScratchDir scratch("recorder_atomic");
  const fs::path dir = scratch / "s";
  const SessionHeader header = SyntheticHeader(40);
  auto recorder = SessionRecorder::Create(dir, header);
  ASSERT_TRUE(recorder.has_value());
  std::atomic<int> reads{0};
  std::atomic<int> bad{0};
  // jthread: stopped and joined on every way out of the test, a failed ASSERT included.
  std::jthread reader([&](const std::stop_token& stop) {
    while (!stop.stop_requested()) {
      std::ifstream in(dir / "session.json");
      std::stringstream text;
      text << in.rdbuf();
      if (!json::accept(text.str())) bad.fetch_add(1);
      reads.fetch_add(1);
    }
  });
  int replaced = 0;
  for (const PlannedRun& plan : header.runs) {
    // Hold the current version open: after the next write it must be an unlinked inode (renamed
    // over), not a file modified in place.
    const int fd = ::open((dir / "session.json").c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(recorder->BeginRun(plan.id, StartFor(plan)).has_value());
    struct stat st {};
    ASSERT_EQ(::fstat(fd, &st), 0);
    replaced += st.st_nlink == 0 ? 1 : 0;
    ::close(fd);
    ASSERT_TRUE(recorder->AppendSamples(SyntheticSamples(plan.id, 20, 1000.0)).has_value());
    ASSERT_TRUE(recorder->EndRun(CompleteEnd(plan)).has_value());
  }
  reader.request_stop();
  reader.join();
  EXPECT_EQ(bad.load(), 0) << "of " << reads.load() << " reads";
  EXPECT_GT(reads.load(), 10);
  EXPECT_EQ(replaced, static_cast<int>(header.runs.size()));
}

}  // namespace
}  // namespace hrgbench::bench
