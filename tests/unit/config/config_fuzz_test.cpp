// Seeded fuzzing of the config loaders with mutations of the shipped bench_configs/station-*,
// sequence-* and limits-* files: byte flips, truncation, duplicated spans and lines, deep
// nesting, huge and malformed numbers, control characters in strings, long strings, many [[runs]].
// Every input must load or be refused with a non-empty message naming the file; nothing may crash.
// Inputs that load are cross-checked (CheckBenchConfigs) with the other two shipped kinds, whose
// errors must name one of the three files.
//
// Provenance: mutations drawn from std::mt19937_64 seeded with kSeed (printed on failure with the
// file, the iteration and the mutations, so a failure replays exactly). 3000 inputs per kind.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_text.hpp"
#include "hrgbench/config/bench_configs.hpp"

namespace hrgbench::bench {
namespace {

using config_file::ConfigError;

namespace fs = std::filesystem;

constexpr std::uint64_t kSeed = 0xC0F1'6F22'2026;
constexpr int kIterationsPerKind = 3000;

using hrgbench::testing::Draw;

enum class Kind { kStation, kSequence, kLimits };

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<fs::path> Shipped(std::string_view prefix) {
  std::vector<fs::path> files;
  for (const auto& entry :
       fs::directory_iterator(fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs")) {
    if (entry.path().filename().string().starts_with(prefix) && entry.path().extension() == ".toml")
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

const std::vector<std::string>& Numbers() {
  static const std::vector<std::string> numbers = {"1e12",
                                                   "1e308",
                                                   "-1e308",
                                                   "1e999",
                                                   "nan",
                                                   "inf",
                                                   "-inf",
                                                   "9223372036854775807",
                                                   "9223372036854775808",
                                                   "-9223372036854775809",
                                                   "0",
                                                   "-0",
                                                   "1e-400",
                                                   "0x7FFFFFFF",
                                                   "1_000",
                                                   "100006",
                                                   "0.0",
                                                   "1e",
                                                   "--1",
                                                   "1.2.3"};
  return numbers;
}

void Mutate(std::string& text, Draw& draw, std::string& log) {
  const std::size_t at = draw.Below(text.size() + 1);
  switch (draw.Below(9)) {
    case 0:
      hrgbench::testing::FlipByte(text, draw, log);
      break;
    case 1:
      hrgbench::testing::Truncate(text, at, log);
      break;
    case 2:
      hrgbench::testing::DuplicateSpan(text, draw, at, 2048, log);
      break;
    case 3: {  // duplicate a whole line (a repeated key or table header)
      const std::size_t begin = text.rfind('\n', at == 0 ? 0 : at - 1);
      const std::size_t start = begin == std::string::npos ? 0 : begin + 1;
      const std::size_t end = std::min(text.find('\n', start), text.size());
      text.insert(start, text.substr(start, end - start) + "\n");
      log += " dupline@" + std::to_string(start);
      break;
    }
    case 4: {  // deep nesting as a new key's value
      static const std::vector<std::size_t> depths = {10, 200, 300, 5000, 100'000};
      const std::size_t depth = draw.Pick(depths);
      const bool inline_table = draw.OneIn(2);
      std::string value = inline_table ? "" : std::string(depth, '[') + std::string(depth, ']');
      if (inline_table) {
        for (std::size_t i = 0; i < depth; ++i) value += "{a=";
        value += "1" + std::string(depth, '}');
      }
      const std::size_t line = text.find('\n', at);
      const std::size_t where = line == std::string::npos ? text.size() : line + 1;
      text.insert(where, "deep = " + value + "\n");
      log += " nest" + std::to_string(depth) + (inline_table ? "{}" : "[]") + "@" +
             std::to_string(where);
      break;
    }
    case 5:  // replace a number with a huge or malformed one
      hrgbench::testing::ReplaceNumber(text, draw, at, ".eE+-_", Numbers(), log);
      break;
    case 6: {  // control characters in a string, escaped or raw
      const std::size_t quote = text.find('"', at);
      if (quote == std::string::npos) break;
      static const std::vector<std::string> bits = {
          "\\u0000", "\\n", "\\u007F", "\\t", std::string(1, '\0'), "\x01", "\\"};
      text.insert(quote + 1, draw.Pick(bits));
      log += " control@" + std::to_string(quote + 1);
      break;
    }
    case 7: {  // a long string
      const std::size_t quote = text.find('"', at);
      if (quote == std::string::npos) break;
      const std::size_t length = draw.OneIn(3) ? 1'100'000 : 300;
      text.insert(quote + 1, std::string(length, 'n'));
      log += " long" + std::to_string(length) + "@" + std::to_string(quote + 1);
      break;
    }
    default: {  // many more [[runs]] (sequences only have them)
      const std::size_t runs = text.find("[[runs]]");
      if (runs == std::string::npos) break;
      const std::size_t next = text.find("[[runs]]", runs + 1);
      const std::string block =
          text.substr(runs, (next == std::string::npos ? text.size() : next) - runs);
      const std::size_t copies = draw.OneIn(2) ? 1001 : draw.Below(20);
      std::string more;
      for (std::size_t i = 0; i < copies; ++i) more += block + "\n";
      text += "\n" + more;
      log += " runs+" + std::to_string(copies);
      break;
    }
  }
}

std::expected<BenchConfigs, ConfigError> Load(Kind kind, const std::string& text,
                                              const fs::path& file, const BenchConfigs& base) {
  BenchConfigs configs = base;
  switch (kind) {
    case Kind::kStation: {
      auto station = ParseStationConfig(text, file);
      if (!station) return std::unexpected(station.error());
      configs.station = *station;
      break;
    }
    case Kind::kSequence: {
      auto sequence = ParseSequenceConfig(text, file);
      if (!sequence) return std::unexpected(sequence.error());
      configs.sequence = *sequence;
      break;
    }
    case Kind::kLimits: {
      auto limits = ParseLimitsConfig(text, file);
      if (!limits) return std::unexpected(limits.error());
      configs.limits = *limits;
      break;
    }
  }
  return configs;
}

TEST(ConfigFuzz, EveryMutationLoadsOrIsRefusedNamingTheFile) {
  const fs::path configs_dir = fs::path(HRGBENCH_SOURCE_DIR) / "bench_configs";
  auto base =
      LoadBenchConfigs(configs_dir / "station-sim.toml", configs_dir / "sequence-production.toml",
                       configs_dir / "limits-example.toml");
  ASSERT_TRUE(base) << base.error().ToString();

  struct Source {
    Kind kind;
    std::vector<fs::path> files;
  };
  const std::vector<Source> sources = {{Kind::kStation, Shipped("station-")},
                                       {Kind::kSequence, Shipped("sequence-")},
                                       {Kind::kLimits, Shipped("limits-")}};
  Draw draw(kSeed);
  int loaded = 0;
  int total = 0;
  for (const Source& source : sources) {
    ASSERT_FALSE(source.files.empty());
    for (int iteration = 0; iteration < kIterationsPerKind; ++iteration) {
      const fs::path& file = draw.Pick(source.files);
      std::string text = ReadFile(file);
      std::string log = "seed " + std::to_string(kSeed) + " " + file.filename().string() +
                        " iteration " + std::to_string(iteration) + ":";
      const std::size_t mutations = 1 + draw.Below(3);
      for (std::size_t m = 0; m < mutations; ++m) Mutate(text, draw, log);
      const fs::path name = "fuzz" / file.filename();
      ++total;
      auto configs = Load(source.kind, text, name, *base);
      if (!configs) {
        const ConfigError& error = configs.error();
        ASSERT_EQ(error.file, name) << log << ": " << error.ToString();
        ASSERT_FALSE(error.message.empty()) << log;
        ASSERT_TRUE(error.ToString().starts_with(name.string())) << log;
        continue;
      }
      ++loaded;
      auto checked = CheckBenchConfigs(*configs);
      if (!checked) {
        const fs::path& at = checked.error().file;
        ASSERT_TRUE(at == name || at == base->station.file || at == base->sequence.file ||
                    at == base->limits.file)
            << log << ": " << checked.error().ToString();
        ASSERT_FALSE(checked.error().message.empty()) << log;
      }
    }
  }
  EXPECT_GT(loaded, total / 50) << "seed " << kSeed;
  std::cout << "seed " << kSeed << ": " << loaded << " of " << total << " inputs loaded\n";
}

}  // namespace
}  // namespace hrgbench::bench
