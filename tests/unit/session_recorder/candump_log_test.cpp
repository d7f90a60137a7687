// candump -L formatting: golden lines after can-utils candump.c, a round trip through the
// independent test-side parser for random frames, and the log writer's append/trim behaviour.

#include "hrgbench/session/candump_log.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "can_frame_assertions.hpp"
#include "candump_log_parser.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;

std::string Line(const hw::CanFrame& frame, std::int64_t t_ns = 1'700'000'000'123'456'789,
                 std::string_view ifname = "can0") {
  char buffer[kMaxCandumpLineLength];
  const std::size_t n = FormatCandumpLine(LoggedCanFrame{t_ns, frame}, ifname, buffer);
  return std::string(buffer, n);
}

hw::CanFrame Frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  hw::CanFrame frame;
  frame.id = id;
  for (std::uint8_t b : bytes) frame.data[frame.length++] = b;
  return frame;
}

fs::path TempDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("hrgbench_candump_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The frame part of a line is hw::FormatCanFrame's, whose golden texts for every kind of frame are
// in tests/unit/hw/can_frame_text_test.cpp; here, what the line adds around it.
TEST(CandumpFormat, GoldenLines) {
  EXPECT_EQ(Line(Frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF})),
            "(1700000000.123456) can0 123#DEADBEEF\n");
  // Zero-padded seconds (%010lu) and microseconds (%06lu); a negative time is written as 0.
  EXPECT_EQ(Line(Frame(0x001, {0x01}), 5'000'001'000), "(0000000005.000001) can0 001#01\n");
  EXPECT_EQ(Line(Frame(0x001, {0x01}), -1), "(0000000000.000000) can0 001#01\n");
}

TEST(CandumpFormat, RefusesBadInterfaceNamesAndSmallBuffers) {
  char buffer[kMaxCandumpLineLength];
  const LoggedCanFrame logged{0, Frame(0x123, {1})};
  EXPECT_EQ(FormatCandumpLine(logged, "", buffer), 0u);
  EXPECT_EQ(FormatCandumpLine(logged, "can 0", buffer), 0u);
  EXPECT_EQ(FormatCandumpLine(logged, "a234567890123456", buffer), 0u);  // 16 > IFNAMSIZ - 1
  char small[10];
  EXPECT_EQ(FormatCandumpLine(logged, "can0", small), 0u);
  // The longest line fits the documented bound.
  hw::CanFrame fd;
  fd.id = 0x1FFFFFFF;
  fd.extended = fd.fd = true;
  fd.length = 64;
  const std::size_t n = FormatCandumpLine(LoggedCanFrame{INT64_MAX, fd}, "a23456789012345", buffer);
  EXPECT_GT(n, 0u);
  EXPECT_LT(n, kMaxCandumpLineLength);
}

TEST(CandumpFormat, RandomFramesRoundTripThroughTheParser) {
  std::mt19937_64 rng(7);  // seeded: reproducible
  constexpr std::uint8_t kFdLengths[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64};
  for (int i = 0; i < 5000; ++i) {
    hw::CanFrame frame;
    const int kind = static_cast<int>(rng() % 5);  // classic std/ext, remote, FD, error
    frame.extended = (rng() & 1) != 0;
    frame.id = static_cast<std::uint32_t>(rng()) &
               (frame.extended ? hw::CanFrame::kExtendedIdMask : hw::CanFrame::kStandardIdMask);
    if (kind == 2) {
      frame.remote = true;
      frame.length = static_cast<std::uint8_t>(rng() % 9);
    } else if (kind == 3) {
      frame.fd = true;
      frame.bit_rate_switch = (rng() & 1) != 0;
      frame.length = kFdLengths[rng() % 16];
    } else if (kind == 4) {
      frame.error = true;
      frame.extended = false;
      frame.id = static_cast<std::uint32_t>(rng()) & 0x1FFu;  // CAN_ERR_* class bits
      frame.length = 8;
    } else {
      frame.length = static_cast<std::uint8_t>(rng() % 9);
    }
    if (!frame.remote) {
      for (std::uint8_t k = 0; k < frame.length; ++k)
        frame.data[k] = static_cast<std::uint8_t>(rng());
    }
    const std::int64_t t_ns = static_cast<std::int64_t>(rng() % 4'000'000'000'000'000'000ull);
    const std::string line = Line(frame, t_ns, "vcan0");
    const auto parsed = testing::ParseCandumpLine(line);
    ASSERT_TRUE(parsed.has_value()) << line;
    EXPECT_EQ(parsed->interface_name, "vcan0");
    EXPECT_EQ(parsed->unix_time_ns, t_ns / 1000 * 1000) << line;
    EXPECT_TRUE(testing::SameFrame(frame, parsed->frame)) << line;
  }
}

TEST(CandumpLogWriter, WritesEveryFrameAndRefusesToOverwrite) {
  const fs::path dir = TempDir("writer");
  const fs::path path = dir / "session.log";
  std::vector<LoggedCanFrame> frames;
  for (std::uint32_t k = 0; k < 3000; ++k) {
    frames.push_back(
        LoggedCanFrame{1'700'000'000'000'000'000 + k * 1'000'000,
                       Frame(0x100 + (k % 16), {std::uint8_t(k), std::uint8_t(k >> 8)})});
  }
  {
    auto log = CandumpLogWriter::Open(path, {.interface_name = "vcan0"});
    ASSERT_TRUE(log.has_value()) << log.error().ToString();
    for (std::size_t k = 0; k < frames.size(); k += 100) {
      ASSERT_TRUE(log->Append(std::span(frames).subspan(k, 100)).has_value());
    }
    EXPECT_EQ(log->frames_written(), frames.size());
    ASSERT_TRUE(log->Close().has_value());
    EXPECT_FALSE(log->Append(frames).has_value());  // closed: kWrongState
  }
  const auto lines = testing::ReadCandumpLog(path.string());
  ASSERT_TRUE(lines.has_value());
  ASSERT_EQ(lines->size(), frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ((*lines)[k].unix_time_ns, frames[k].unix_time_ns);
    EXPECT_TRUE(testing::SameFrame(frames[k].frame, (*lines)[k].frame)) << k;
  }
  auto again = CandumpLogWriter::Open(path, {.interface_name = "vcan0"});
  ASSERT_FALSE(again.has_value());
  EXPECT_EQ(again.error().kind, RecordErrorKind::kInvalidArgument);
  EXPECT_FALSE(CandumpLogWriter::Open(dir / "x.log", {.interface_name = "bad name"}).has_value());
  fs::remove_all(dir);
}

TEST(CandumpLogWriter, AppendCutsALineTornByACrash) {
  const fs::path dir = TempDir("append");
  const fs::path path = dir / "session.log";
  {
    std::ofstream out(path);
    out << "(1700000000.000001) can0 123#01\n(1700000000.000002) can0 12";  // torn last line
  }
  CandumpLogOptions options;
  options.append = true;
  auto log = CandumpLogWriter::Open(path, options);
  ASSERT_TRUE(log.has_value()) << log.error().ToString();
  const LoggedCanFrame frame{1'700'000'000'000'003'000, Frame(0x321, {0xAB})};
  ASSERT_TRUE(log->Append(std::span(&frame, 1)).has_value());
  ASSERT_TRUE(log->Close().has_value());
  const auto lines = testing::ReadCandumpLog(path.string());
  ASSERT_TRUE(lines.has_value());
  ASSERT_EQ(lines->size(), 2u);
  EXPECT_EQ((*lines)[0].frame.id, 0x123u);
  EXPECT_TRUE(testing::SameFrame(frame.frame, (*lines)[1].frame));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hrgbench::bench
