// candump -L reading: lines as can-utils writes them (typed here, not made by our writer), a round
// trip through CandumpLogWriter, and damage: a bad line, a torn last line, an overlong line, a
// second interface, the bounds. Damage ends the reading at the line it names and keeps what came
// before.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "can_frame_assertions.hpp"
#include "hrgbench/session/candump_log.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;
using testing::SameFrame;

// This process's scratch folder, removed when the process ends (each test runs as its own
// process: a folder left per test piled up in the scratch space, 20 per pass of the suite).
const fs::path& ScratchDir() {
  struct Scratch {
    fs::path dir =
        fs::temp_directory_path() / ("hrgbench_candump_read_" + std::to_string(::getpid()));
    ~Scratch() {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
  };
  static const Scratch scratch;
  return scratch.dir;
}

fs::path TempFile(const std::string& name, const std::string& text) {
  const fs::path& dir = ScratchDir();
  fs::create_directories(dir);
  const fs::path path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

struct ReadAll {
  std::vector<LoggedCanFrame> frames;
  std::optional<CandumpLogDamage> damage;
  std::uint64_t error_frames = 0;
};

ReadAll Read(const fs::path& path, const CandumpLogReadLimits& limits = {}) {
  auto reader = CandumpLogReader::Open(path, limits);
  EXPECT_TRUE(reader.has_value()) << (reader ? "" : reader.error().ToString());
  ReadAll out;
  if (!reader) return out;
  while (auto frame = reader->Next()) out.frames.push_back(*frame);
  EXPECT_FALSE(reader->Next().has_value());  // the end (or the damage) stays the end
  out.damage = reader->damage();
  out.error_frames = reader->error_frames();
  return out;
}

hw::CanFrame Frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  hw::CanFrame frame;
  frame.id = id;
  for (std::uint8_t b : bytes) frame.data[frame.length++] = b;
  return frame;
}

// Lines as can-utils' candump -L prints them (lib.c sprint_canframe, candump.c "(%010lu.%06lu)").
TEST(CandumpReader, ReadsWhatCandumpWrites) {
  const fs::path path = TempFile("candump.log",
                                 "(1700000000.123456) vcan0 123#DEADBEEF\n"
                                 "(1700000000.123457) vcan0 1ABCDEF0#00\n"
                                 "(1700000000.200000) vcan0 7FF#R\n"
                                 "(1700000000.300000) vcan0 102##1" +
                                     std::string(128, 'A') +
                                     "\n"
                                     "(1700000000.400000) vcan0 20000004#0000080000000000\n"
                                     "(0000000005.000001) vcan0 050#\n");
  const ReadAll read = Read(path);
  EXPECT_FALSE(read.damage) << read.damage->message;
  ASSERT_EQ(read.frames.size(), 5u);
  EXPECT_EQ(read.error_frames, 1u);
  EXPECT_EQ(read.frames[0].unix_time_ns, 1'700'000'000'123'456'000);
  EXPECT_TRUE(SameFrame(Frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF}), read.frames[0].frame));
  EXPECT_TRUE(read.frames[1].frame.extended);
  EXPECT_EQ(read.frames[1].frame.id, 0x1ABCDEF0u);
  EXPECT_TRUE(read.frames[2].frame.remote);
  EXPECT_TRUE(read.frames[3].frame.fd);
  EXPECT_TRUE(read.frames[3].frame.bit_rate_switch);
  EXPECT_EQ(read.frames[3].frame.length, 64);
  EXPECT_EQ(read.frames[3].frame.data[63], 0xAA);
  EXPECT_EQ(read.frames[4].unix_time_ns, 5'000'001'000);
  EXPECT_EQ(read.frames[4].frame.length, 0);
}

TEST(CandumpReader, ReadsBackWhatTheWriterWrote) {
  const fs::path dir =
      fs::temp_directory_path() / ("hrgbench_candump_rt_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::mt19937_64 random(7);
  std::vector<LoggedCanFrame> written;
  for (int i = 0; i < 2000; ++i) {
    LoggedCanFrame logged;
    logged.unix_time_ns = 1'700'000'000'000'000'000 + static_cast<std::int64_t>(i) * 1'000'000 +
                          static_cast<std::int64_t>(random() % 1000) * 1000;  // whole µs
    hw::CanFrame& f = logged.frame;
    switch (i % 4) {
      case 0:
        f.id = random() & 0x7FF;
        break;
      case 1:
        f.id = random() & 0x1FFFFFFF;
        f.extended = true;
        break;
      case 2:
        f.id = random() & 0x7FF;
        f.fd = true;
        f.bit_rate_switch = (i % 8) == 2;
        break;
      default:
        f.id = random() & 0x7FF;
        f.remote = true;
        break;
    }
    f.length = f.fd ? 64 : static_cast<std::uint8_t>(random() % 9);
    if (!f.remote)
      for (std::uint8_t k = 0; k < f.length; ++k) f.data[k] = static_cast<std::uint8_t>(random());
    written.push_back(logged);
  }
  {
    auto writer = CandumpLogWriter::Open(dir / "session.log");
    ASSERT_TRUE(writer.has_value());
    ASSERT_TRUE(writer->Append(written).has_value());
    ASSERT_TRUE(writer->Close().has_value());
  }
  const ReadAll read = Read(dir / "session.log");
  EXPECT_FALSE(read.damage);
  ASSERT_EQ(read.frames.size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    ASSERT_EQ(read.frames[i].unix_time_ns, written[i].unix_time_ns) << i;
    ASSERT_TRUE(SameFrame(written[i].frame, read.frames[i].frame)) << i;
  }
  fs::remove_all(dir);
}

constexpr const char* kGood =
    "(1700000000.000001) can0 100#0001000200030A\n"
    "(1700000000.000002) can0 101#0004000500060B\n";

struct DamageCase {
  std::string name;
  std::string third_line;  // what follows the two good lines
  std::string message;     // a part of the damage message
};

TEST(CandumpReader, DamageEndsTheReadingAtTheLineItNames) {
  const std::vector<DamageCase> cases = {
      {"bad hex", "(1700000000.000003) can0 10G#00\n(1700000000.000004) can0 100#00\n",
       "frame text '10G#00' does not parse"},
      {"bad stamp", "(17000x0000.000003) can0 100#00\n", "is not SECONDS.MICROSECONDS"},
      {"no interface", "(1700000000.000003)can0 100#00\n", "no blank after the time stamp"},
      {"no frame", "(1700000000.000003) can0\n", "no frame text"},
      {"other interface", "(1700000000.000003) can1 100#00\n",
       "interface 'can1', the log's is "
       "'can0'"},
      {"torn", "(1700000000.000003) can0 100#00010", "cut off (no end of line"},
      {"overlong", std::string(5000, 'A') + "\n", "longer than any log line"},
      {"binary", "(1700000000.000003) can0 100#\x01\x02\n", "does not parse"},
  };
  for (const DamageCase& c : cases) {
    SCOPED_TRACE(c.name);
    const ReadAll read = Read(TempFile("damaged.log", std::string(kGood) + c.third_line));
    EXPECT_EQ(read.frames.size(), 2u);  // what came before the damage
    ASSERT_TRUE(read.damage);
    EXPECT_EQ(read.damage->line, 3u);
    EXPECT_EQ(read.damage->message.rfind("line 3: ", 0), 0u) << read.damage->message;
    EXPECT_NE(read.damage->message.find(c.message), std::string::npos) << read.damage->message;
  }
}

TEST(CandumpReader, BoundsAreDamageOrRefusal) {
  const fs::path path = TempFile("bounded.log", std::string(kGood) + kGood);
  CandumpLogReadLimits few;
  few.max_frames = 3;
  const ReadAll read = Read(path, few);
  EXPECT_EQ(read.frames.size(), 3u);
  ASSERT_TRUE(read.damage);
  EXPECT_NE(read.damage->message.find("more than 3 frames"), std::string::npos);

  CandumpLogReadLimits small;
  small.max_bytes = 10;
  auto refused = CandumpLogReader::Open(path, small);
  ASSERT_FALSE(refused.has_value());
  EXPECT_EQ(refused.error().kind, RecordErrorKind::kInvalidArgument);
  EXPECT_NE(refused.error().ToString().find("bounded.log"), std::string::npos);

  auto missing = CandumpLogReader::Open(path.parent_path() / "absent.log");
  ASSERT_FALSE(missing.has_value());
  EXPECT_NE(missing.error().ToString().find("absent.log"), std::string::npos);
}

TEST(CandumpReader, AnEmptyLogIsAnEmptyRecord) {
  const ReadAll read = Read(TempFile("empty.log", ""));
  EXPECT_TRUE(read.frames.empty());
  EXPECT_FALSE(read.damage);
}

}  // namespace
}  // namespace hrgbench::bench
