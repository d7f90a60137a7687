// The candump reader on damaged logs (seeded; the seed and mutations are printed on failure):
// byte flips, truncation, duplicated spans. Whatever the bytes, reading ends, and it accounts for
// every line: a log without damage yields one frame (or counted error frame) per line, a damaged
// one yields one per line before the line it names, which is a line of the file.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_text.hpp"
#include "hrgbench/session/candump_log.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;
using testing::Draw;

std::string CleanLog(Draw& draw) {
  std::string text;
  char line[kMaxCandumpLineLength];
  const std::size_t lines = 1 + draw.Below(60);
  for (std::size_t i = 0; i < lines; ++i) {
    LoggedCanFrame logged;
    logged.unix_time_ns = 1'700'000'000'000'000'000 + static_cast<std::int64_t>(i) * 1'000'000;
    hw::CanFrame& f = logged.frame;
    f.id = static_cast<std::uint32_t>(draw.Below(0x800));
    switch (draw.Below(4)) {
      case 0:
        f.fd = true;
        f.bit_rate_switch = true;
        f.length = 64;
        break;
      case 1:
        f.error = true;
        f.id = 0x04;
        f.length = 8;
        break;
      default:
        f.length = static_cast<std::uint8_t>(draw.Below(9));
        break;
    }
    for (std::uint8_t k = 0; k < f.length; ++k) f.data[k] = static_cast<std::uint8_t>(draw.Bits());
    const std::size_t n = FormatCandumpLine(logged, "can0", line);
    text.append(line, n);
  }
  return text;
}

TEST(CandumpReaderFuzz, EveryLineIsAccountedFor) {
  const fs::path path =
      fs::temp_directory_path() / ("hrgbench_candump_fuzz_" + std::to_string(::getpid()) + ".log");
  for (std::uint64_t seed = 1; seed <= 400; ++seed) {
    Draw draw(seed);
    std::string text = CleanLog(draw);
    std::string log = "seed " + std::to_string(seed) + ":";
    const std::size_t mutations = draw.Below(4);
    for (std::size_t m = 0; m < mutations; ++m) {
      switch (draw.Below(3)) {
        case 0:
          testing::FlipByte(text, draw, log);
          break;
        case 1:
          testing::Truncate(text, draw.Below(text.size() + 1), log);
          break;
        default:
          testing::DuplicateSpan(text, draw, draw.Below(text.size() + 1), 200, log);
          break;
      }
    }
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    auto reader = CandumpLogReader::Open(path);
    ASSERT_TRUE(reader.has_value()) << log;
    std::uint64_t frames = 0;
    while (reader->Next()) ++frames;
    ASSERT_EQ(frames, reader->frames_read()) << log;
    const auto newlines = static_cast<std::uint64_t>(std::count(text.begin(), text.end(), '\n'));
    const std::uint64_t accounted = reader->frames_read() + reader->error_frames();
    if (!reader->damage()) {
      // Clean: the text ends at a line's end, every line read.
      ASSERT_TRUE(text.empty() || text.back() == '\n') << log;
      ASSERT_EQ(accounted, newlines) << log;
    } else {
      const CandumpLogDamage& damage = *reader->damage();
      ASSERT_GE(damage.line, 1u) << log;
      ASSERT_LE(damage.line, newlines + 1) << log << " " << damage.message;
      ASSERT_EQ(accounted, damage.line - 1) << log << " " << damage.message;
      ASSERT_EQ(damage.message.rfind("line " + std::to_string(damage.line) + ": ", 0), 0u)
          << log << " " << damage.message;
    }
  }
  fs::remove(path);
}

}  // namespace
}  // namespace hrgbench::bench
