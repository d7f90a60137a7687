// Seeded fuzzing of the session reader. A valid session is written by the session writer (two runs
// with an extra column, metadata nested like a bench session's), then mutated: byte flips,
// truncation, duplicated and deleted spans, deep nesting (also as the value of a key), huge and
// malformed numbers, control characters. Every input must either load, or be refused with a
// non-empty message naming a file of the session; nothing may crash. An accepted session must also
// survive the writer and read back (the writer refuses exactly what the reader refuses).
//
// Provenance: mutations drawn from std::mt19937_64 seeded with kSeed (printed on failure, with the
// iteration and the mutations, so a failure replays exactly). 3000 inputs, under a second
// (RelWithDebInfo, this 2-core machine).

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_text.hpp"
#include "hrgbench/session/session.hpp"
#include "session_test_util.hpp"

namespace hrgbench::session {
namespace {

using testing::ReadText;
using testing::TempDir;
using testing::WriteText;

constexpr std::uint64_t kSeed = 0x5E55'1011'F022;
constexpr int kIterations = 3000;

// Small portable draws (the standard distributions differ between libraries; the seed must
// replay the same inputs everywhere).
using hrgbench::testing::Draw;

Session BaseSession() {
  Session session;
  session.serial = "SN-FUZZ-1";
  session.sample_rate_hz = 100.0;
  session.runs = {{1, "runs/run-001.csv", -0.5, "complete"},
                  {2, "runs/run-002.csv", 0.5, "complete"},
                  {3, "runs/run-003.csv", 1.0, "aborted"}};
  session.document = nlohmann::json::object();
  session.document["station"] = {{"name", "bench-fuzz"}, {"axis_enu", {0.0, 0.0, 1.0}}};
  session.document["simulation"] = {
      {"delta", {-0.001, 0.3, 0, 0, 0, 0}}, {"xi", {0.01, 0, 0, 0}}, {"sigma", 1e-4}};
  session.document["resumed_at"] = nlohmann::json::array(
      {{{"previous_state", "running"}, {"previous_outcome", {{"estimate", {{"delta2", 0.3}}}}}}});
  return session;
}

RunSamples BaseSamples(double phase) {
  constexpr int kSamples = 40;
  RunSamples samples;
  samples.y.resize(4, kSamples);
  std::vector<double> temperature;
  for (int k = 0; k < kSamples; ++k) {
    const double t = k * 0.01;
    samples.t_s.push_back(t);
    samples.y.col(k) << std::cos(t + phase), std::sin(t + phase), 1e-3 * k, -2.5e-7 * k;
    temperature.push_back(25.0 + 1e-3 * k);
  }
  samples.extra_columns["temp_c"] = temperature;
  return samples;
}

const std::vector<std::string>& Numbers() {
  static const std::vector<std::string> numbers = {"1e999",
                                                   "-1e999",
                                                   "1e308",
                                                   "1e-400",
                                                   "123456789012345678901234567890",
                                                   "NaN",
                                                   "inf",
                                                   "-0",
                                                   "0x10",
                                                   "+1",
                                                   "4294967296",
                                                   "-2147483649",
                                                   "1.7976931348623157e308",
                                                   "1e",
                                                   "--1",
                                                   "1..2",
                                                   "0",
                                                   "9223372036854775808"};
  return numbers;
}

// End of the JSON value starting at `start` (brackets balanced outside strings; a scalar ends at
// a delimiter). Works on broken text too: it only needs an end, not a parse.
std::size_t ValueEnd(const std::string& text, std::size_t start) {
  std::size_t depth = 0;
  bool in_string = false;
  for (std::size_t i = start; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
        if (depth == 0) return i + 1;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if (c == ']' || c == '}') {
      if (depth == 0) return i;
      if (--depth == 0) return i + 1;
    } else if (depth == 0 && (c == ',' || c == '\n')) {
      return i;
    }
  }
  return text.size();
}

// One mutation of `text`, described in `log`.
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
      hrgbench::testing::DuplicateSpan(text, draw, at, 4096, log);
      break;
    case 3: {  // delete a span
      const std::size_t length = draw.Below(std::min<std::size_t>(text.size() - at, 64) + 1);
      text.erase(at, length);
      log += " del[" + std::to_string(at) + "+" + std::to_string(length) + "]";
      break;
    }
    case 4: {  // deep nesting, closed or not
      static const std::vector<std::size_t> depths = {63, 64, 65, 200, 5000, 100'000};
      const std::size_t depth = draw.Pick(depths);
      const bool closed = draw.OneIn(2);
      const char open = draw.OneIn(2) ? '[' : '{';
      std::string nest(depth, open);
      if (closed) nest += std::string(depth, open == '[' ? ']' : '}');
      text.insert(at, nest);
      log += " nest" + std::to_string(depth) + (closed ? "closed" : "") + "@" + std::to_string(at);
      break;
    }
    case 5:  // replace a number token with a huge or malformed one
      hrgbench::testing::ReplaceNumber(text, draw, at, ".eE+-", Numbers(), log);
      break;
    case 6: {  // control characters and escapes, raw or escaped
      static const std::vector<std::string> bits = {
          std::string(1, '\0'), "\\u0000", "\n", "\r", "\x7F", "\\", "\"", "\xFF\xFE", ",", "\t"};
      const std::string& bit = draw.Pick(bits);
      text.insert(at, bit);
      log += " insert@" + std::to_string(at);
      break;
    }
    case 8: {  // the value of a key replaced by deep nesting (what the reader then inspects)
      const std::size_t colon = text.find("\": ", at);
      if (colon == std::string::npos) break;
      const std::size_t start = colon + 3;
      static const std::vector<std::size_t> depths = {64, 65, 100'000};
      const std::size_t depth = draw.Pick(depths);
      const char open = draw.OneIn(2) ? '[' : '{';
      std::string nest(depth, '[');
      if (open == '{') nest = "{\"k\": " + std::string(depth - 1, '[');
      nest += std::string(depth - 1, ']') + (open == '{' ? "}" : "]");
      text.replace(start, ValueEnd(text, start) - start, nest);
      log += " value" + std::to_string(depth) + "@" + std::to_string(start);
      break;
    }
    default: {  // a long run of one character (long names, long lines, long numbers)
      const std::size_t length = draw.OneIn(4) ? 70'000 : 300;
      text.insert(at, std::string(length, draw.OneIn(2) ? 'x' : '9'));
      log += " long" + std::to_string(length) + "@" + std::to_string(at);
      break;
    }
  }
}

// A scratch directory on tmpfs (/dev/shm) when there is one, else under the temp dir. The loop
// rewrites a file twice per input; on ext4 rewriting a truncated file forces its data to disk on
// close (auto_da_alloc, 2 ms here), and the writer fsyncs: 3000 inputs took 7-11 s in /tmp.
class ScratchDir {
 public:
  ScratchDir() {
    std::error_code ec;
    const std::filesystem::path shm = "/dev/shm";
    if (std::filesystem::is_directory(shm, ec) && ::access(shm.c_str(), W_OK) == 0) {
      path_ = shm / ("hrgbench_session_fuzz_" + std::to_string(::getpid()));
      std::filesystem::create_directories(path_, ec);
      if (!ec) return;
    }
    fallback_.emplace();
    path_ = fallback_->path();
  }
  ~ScratchDir() {
    std::error_code ec;
    if (!fallback_) std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::optional<TempDir> fallback_;
};

bool StartsWith(const std::filesystem::path& path, const std::filesystem::path& prefix) {
  return path.string().starts_with(prefix.string());
}

TEST(SessionFuzz, EveryMutationLoadsOrIsRefusedNamingAFile) {
  const ScratchDir dir;
  const std::filesystem::path session_dir = dir.path() / "s";
  Session base = BaseSession();
  ASSERT_TRUE(WriteSessionJson(session_dir, base));
  const std::vector<std::string> files = {"session.json", "runs/run-001.csv", "runs/run-002.csv"};
  ASSERT_TRUE(WriteRunCsv(session_dir / files[1], BaseSamples(0.0)));
  ASSERT_TRUE(WriteRunCsv(session_dir / files[2], BaseSamples(1.0)));
  std::vector<std::string> base_texts;
  for (const std::string& file : files) base_texts.push_back(ReadText(session_dir / file));
  {
    const auto session = ReadSession(session_dir);
    ASSERT_TRUE(session) << session.error().ToString();
    ASSERT_EQ(session->loaded_run_ids.size(), 2u);
  }

  Draw draw(kSeed);
  int loaded = 0;
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    std::vector<std::string> texts = base_texts;
    const std::size_t target = draw.Below(texts.size() + 1) % texts.size();  // json twice as often
    std::string log = "seed " + std::to_string(kSeed) + " iteration " + std::to_string(iteration) +
                      " " + files[target] + ":";
    const std::size_t mutations = 1 + draw.Below(3);
    for (std::size_t m = 0; m < mutations; ++m) Mutate(texts[target], draw, log);
    WriteText(session_dir / files[target], texts[target]);

    const auto session = ReadSession(session_dir);
    if (session) {
      ++loaded;
      ASSERT_EQ(session->loaded_run_ids.size(), session->loaded_samples.size()) << log;
      for (const RunSamples& samples : session->loaded_samples) {
        ASSERT_EQ(static_cast<std::size_t>(samples.y.cols()), samples.size()) << log;
      }
      // Whatever the reader accepts, the writer writes and the reader reads back.
      const std::filesystem::path copy = dir.path() / "copy";
      const auto written = WriteSessionJson(copy, *session);
      ASSERT_TRUE(written) << log << ": " << written.error().ToString();
      const auto again = ReadSession(copy, ReadOptions{.load_samples = false});
      ASSERT_TRUE(again) << log << ": " << again.error().ToString();
    } else {
      const SessionError& error = session.error();
      ASSERT_FALSE(error.message.empty()) << log;
      ASSERT_TRUE(StartsWith(error.file, session_dir)) << log << ": " << error.ToString();
      ASSERT_NE(error.ToString().find(error.file.string()), std::string::npos) << log;
    }
    WriteText(session_dir / files[target], base_texts[target]);  // back to the valid session
  }
  // The mutations must leave some inputs valid (else the test only exercises refusal).
  EXPECT_GT(loaded, kIterations / 50) << "seed " << kSeed;
  std::cout << "seed " << kSeed << ": " << loaded << " of " << kIterations << " inputs loaded\n";
}

}  // namespace
}  // namespace hrgbench::session
