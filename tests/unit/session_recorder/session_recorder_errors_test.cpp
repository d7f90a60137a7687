// SessionRecorder refusals: invalid headers, calls out of order, samples the CSV cannot hold. Each
// is a value (std::expected), none throws, and none damages what is already recorded.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_recorder.hpp"
#include "record_test_dir.hpp"
#include "synthetic_gyro_record.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::SyntheticHeader;
using testing::SyntheticSamples;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

RecordErrorKind CreateError(const fs::path& dir, const SessionHeader& header) {
  auto created = SessionRecorder::Create(dir, header);
  EXPECT_FALSE(created.has_value());
  return created ? RecordErrorKind::kIo : created.error().kind;
}

TEST(SessionRecorderErrors, CreateRefusesInvalidHeaders) {
  ScratchDir scratch("recorder_header");
  SessionHeader header = SyntheticHeader(2);
  header.unit_serial.clear();
  EXPECT_EQ(CreateError(scratch / "a", header), RecordErrorKind::kInvalidArgument);
  header = SyntheticHeader(2);
  header.runs[1].id = 1;
  EXPECT_EQ(CreateError(scratch / "b", header), RecordErrorKind::kInvalidArgument);
  header = SyntheticHeader(2);
  header.runs[0].sample_rate_hz = 0.0;
  EXPECT_EQ(CreateError(scratch / "c", header), RecordErrorKind::kInvalidArgument);
  header = SyntheticHeader(2);
  header.runs[0].a = kNaN;
  EXPECT_EQ(CreateError(scratch / "d", header), RecordErrorKind::kInvalidArgument);
  header = SyntheticHeader(0);
  EXPECT_EQ(CreateError(scratch / "e", header), RecordErrorKind::kInvalidArgument);
  header = SyntheticHeader(1);
  header.can_interface = "can 0";
  EXPECT_EQ(CreateError(scratch / "f", header), RecordErrorKind::kInvalidArgument);
  // Nothing was created for the refused headers that were caught before touching the disk.
  EXPECT_FALSE(fs::exists(scratch / "a"));
}

TEST(SessionRecorderErrors, CreateRefusesANonEmptyDirectory) {
  ScratchDir scratch("recorder_nonempty");
  fs::create_directories(scratch / "s");
  std::ofstream(scratch / "s" / "notes.txt") << "keep me\n";
  EXPECT_EQ(CreateError(scratch / "s", SyntheticHeader(1)), RecordErrorKind::kDirectoryNotEmpty);
  EXPECT_TRUE(fs::exists(scratch / "s" / "notes.txt"));
  EXPECT_FALSE(fs::exists(scratch / "s" / "session.json"));
  // An existing empty directory is fine.
  fs::create_directories(scratch / "empty");
  EXPECT_TRUE(SessionRecorder::Create(scratch / "empty", SyntheticHeader(1)).has_value());
}

TEST(SessionRecorderErrors, CallsOutOfOrderAreWrongState) {
  ScratchDir scratch("recorder_order");
  auto recorder = SessionRecorder::Create(scratch / "s", SyntheticHeader(2));
  ASSERT_TRUE(recorder.has_value());
  EXPECT_EQ(recorder->AppendSamples(SyntheticSamples(1, 2, 1000.0)).error().kind,
            RecordErrorKind::kWrongState);
  EXPECT_EQ(recorder->EndRun({}).error().kind, RecordErrorKind::kWrongState);
  EXPECT_EQ(recorder->BeginRun(7, {}).error().kind, RecordErrorKind::kInvalidArgument);
  ASSERT_TRUE(recorder->BeginRun(1, {}).has_value());
  EXPECT_EQ(recorder->BeginRun(2, {}).error().kind, RecordErrorKind::kWrongState);
  EXPECT_EQ(recorder->open_run_id(), 1);
}

TEST(SessionRecorderErrors, EndRunRefusalsKeepTheRunOpen) {
  ScratchDir scratch("recorder_endrun");
  auto recorder = SessionRecorder::Create(scratch / "s", SyntheticHeader(1));
  ASSERT_TRUE(recorder.has_value());
  ASSERT_TRUE(recorder->BeginRun(1, {}).has_value());
  RunEnd end;  // complete, but Ω is NaN
  EXPECT_EQ(recorder->EndRun(end).error().kind, RecordErrorKind::kInvalidArgument);
  end.status = "finished";
  end.omega_rad_s = 0.1;
  EXPECT_EQ(recorder->EndRun(end).error().kind, RecordErrorKind::kInvalidArgument);
  end.status = kRunAborted;  // no reason
  EXPECT_EQ(recorder->EndRun(end).error().kind, RecordErrorKind::kInvalidArgument);
  EXPECT_EQ(recorder->open_run_id(), 1);
  end.reason = "table fault";
  EXPECT_TRUE(recorder->EndRun(end).has_value());
  EXPECT_EQ(recorder->Close({OutcomeKind::kError, "", {}, {}, {}}).error().kind,
            RecordErrorKind::kInvalidArgument);  // ERROR needs a reason
}

TEST(SessionRecorderErrors, SamplesTheCsvCannotHoldAreRefusedAndNothingOfTheBatchIsWritten) {
  ScratchDir scratch("recorder_samples");
  const fs::path dir = scratch / "s";
  RecorderOptions options;
  options.flush_interval_ns = 0;
  auto recorder = SessionRecorder::Create(dir, SyntheticHeader(1), options);
  ASSERT_TRUE(recorder.has_value());
  RunStart start;
  start.with_temperature = true;
  start.with_resonant_frequency = true;
  ASSERT_TRUE(recorder->BeginRun(1, start).has_value());
  auto samples = SyntheticSamples(1, 10, 1000.0);
  ASSERT_TRUE(recorder->AppendSamples(std::span(samples).first(5)).has_value());
  const auto size_before = fs::file_size(dir / "runs" / "run-001.csv.partial");

  auto bad = samples;
  bad[7].y[2] = kNaN;
  EXPECT_EQ(recorder->AppendSamples(std::span(bad).subspan(5)).error().kind,
            RecordErrorKind::kInvalidArgument);
  bad = samples;
  bad[6].t_s = bad[5].t_s;  // not strictly increasing
  EXPECT_EQ(recorder->AppendSamples(std::span(bad).subspan(5)).error().kind,
            RecordErrorKind::kInvalidArgument);
  EXPECT_EQ(recorder->AppendSamples(std::span(samples).subspan(4, 2)).error().kind,
            RecordErrorKind::kInvalidArgument);  // repeats the last appended t_s
  bad = samples;
  bad[9].temperature_c = kNaN;  // enabled optional column
  EXPECT_EQ(recorder->AppendSamples(std::span(bad).subspan(5)).error().kind,
            RecordErrorKind::kInvalidArgument);
  bad = samples;
  bad[8].resonant_frequency_hz = HUGE_VAL;  // the other one
  const auto refused = recorder->AppendSamples(std::span(bad).subspan(5));
  ASSERT_FALSE(refused.has_value());
  EXPECT_NE(refused.error().message.find("non-finite freq_hz inf"), std::string::npos)
      << refused.error().message;
  EXPECT_EQ(fs::file_size(dir / "runs" / "run-001.csv.partial"), size_before);

  ASSERT_TRUE(recorder->AppendSamples(std::span(samples).subspan(5)).has_value());
  RunEnd end;
  end.omega_rad_s = 0.1;
  ASSERT_TRUE(recorder->EndRun(end).has_value());
  auto read = session::ReadRunCsv(dir / "runs" / "run-001.csv");
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  EXPECT_EQ(read->size(), 10u);
  EXPECT_FALSE(read->extra_columns.contains("omega_meas_rad_s"));
  EXPECT_TRUE(read->extra_columns.contains("temp_c"));
  EXPECT_TRUE(read->extra_columns.contains("freq_hz"));
}

TEST(SessionRecorderErrors, ResumeRefusesWhatItDidNotWrite) {
  ScratchDir scratch("recorder_resume_bad");
  EXPECT_EQ(SessionRecorder::OpenForResume(scratch / "missing").error().kind,
            RecordErrorKind::kBadSession);
  // A session of the estimator format without the bench's keys (e.g. written by hrg-sim).
  session::Session plain;
  plain.serial = "X";
  plain.sample_rate_hz = 100.0;
  plain.runs.push_back({1, "runs/run-001.csv", 0.1, "planned"});
  ASSERT_TRUE(session::WriteSessionJson(scratch / "plain", plain).has_value());
  EXPECT_EQ(SessionRecorder::OpenForResume(scratch / "plain").error().kind,
            RecordErrorKind::kBadSession);
}

}  // namespace
}  // namespace hrgbench::bench
