// The CAN log as can-utils reads it (log2asc, when installed: apt-get install can-utils), and the
// recorder's streaming throughput (printed, recorded as a test property; no threshold).

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "hrgbench/session/candump_log.hpp"
#include "record_test_dir.hpp"
#include "recorder_fixture.hpp"
#include "required_tool.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;

TEST(CandumpLogCompat, Log2ascReadsEveryKindOfFrame) {
  HRGBENCH_REQUIRE(std::system("command -v log2asc > /dev/null 2>&1") == 0,
                   "log2asc (can-utils) not installed");
  testing::ScratchDir scratch("record_log2asc");
  const fs::path log_path = scratch / "session.log";
  std::vector<LoggedCanFrame> frames(5);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    frames[k].unix_time_ns = 1'700'000'000'000'000'000 + static_cast<std::int64_t>(k) * 100'000'000;
    frames[k].frame.id = 0x123;
    frames[k].frame.length = 4;
    frames[k].frame.data = {0xDE, 0xAD, 0xBE, 0xEF};
  }
  frames[1].frame.extended = true;
  frames[1].frame.id = 0x1ABCDEF0;
  frames[2].frame.remote = true;
  frames[3].frame.fd = true;
  frames[3].frame.bit_rate_switch = true;
  frames[4].frame = hw::CanFrame{};
  frames[4].frame.error = true;
  frames[4].frame.id = 0x40;  // CAN_ERR_BUSOFF
  frames[4].frame.length = 8;
  {
    auto log = CandumpLogWriter::Open(log_path, {.interface_name = "can0"});
    ASSERT_TRUE(log.has_value());
    ASSERT_TRUE(log->Append(frames).has_value());
    ASSERT_TRUE(log->Close().has_value());
  }
  const fs::path asc = scratch / "session.asc";
  const std::string command = "log2asc -I " + log_path.string() + " -O " + asc.string() + " can0";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream in(asc);
  std::stringstream text;
  text << in.rdbuf();
  const std::string out = text.str();
  EXPECT_NE(out.find("123             Rx   d 4 DE AD BE EF"), std::string::npos) << out;
  EXPECT_NE(out.find("1ABCDEF0x       Rx   d 4 DE AD BE EF"), std::string::npos) << out;
  EXPECT_NE(out.find("123             Rx   r 4"), std::string::npos) << out;
  EXPECT_NE(out.find("CANFD"), std::string::npos) << out;
  EXPECT_NE(out.find("ErrorFrame"), std::string::npos) << out;
}

// 200 000 samples with both optional columns, in batches of 1000 as a drain loop would hand them.
TEST(RecorderThroughput, StreamsARunToDisk) {
  testing::ScratchDir scratch("record_throughput");
  SessionHeader header = testing::SyntheticHeader(1, 10'000.0);
  header.runs[0].free_run_s = 20.0;
  auto recorder = SessionRecorder::Create(scratch / "session", header);
  ASSERT_TRUE(recorder.has_value());
  const auto samples = testing::SyntheticSamples(1, 200'000, 10'000.0, 0.1);
  RunStart start = record_test::StartFor(header.runs[0]);
  start.with_measured_omega = start.with_temperature = true;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(recorder->BeginRun(1, start).has_value());
  for (std::size_t k = 0; k < samples.size(); k += 1000) {
    ASSERT_TRUE(recorder->AppendSamples(std::span(samples).subspan(k, 1000)).has_value());
  }
  ASSERT_TRUE(recorder->EndRun(record_test::CompleteEnd(header.runs[0])).has_value());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double bytes =
      static_cast<double>(fs::file_size(scratch / "session" / "runs" / "run-001.csv"));
  const double mb_s = bytes / 1e6 / seconds;
  const double samples_s = static_cast<double>(samples.size()) / seconds;
  std::printf(
      "recorder: %.0f samples (%.1f MB) in %.3f s incl. fsync+rename: %.1f MB/s, %.0f "
      "samples/s\n",
      static_cast<double>(samples.size()), bytes / 1e6, seconds, mb_s, samples_s);
  ::testing::Test::RecordProperty("mb_per_s", std::to_string(mb_s));
  auto read = session::ReadRunCsv(scratch / "session" / "runs" / "run-001.csv");
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->size(), samples.size());
}

}  // namespace
}  // namespace hrgbench::bench
