// A sequence's operator prompts ([[prompts]], issue 26 §1): where each is asked, its text and its
// image, and every mistake refused naming file, line, key and value.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hrgbench/config/sequence_config.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;

const std::string kHead = R"([sequence]
name = "q"

[defaults]
a = 1.0
b = 0.0
theta_rad = 0.0
free_run_s = 10.0
sample_rate_hz = 100

[[runs]]
omega_rad_s = 0.5

[[runs]]
omega_rad_s = -0.5
)";

// A folder of its own with the sequence file in it (images are resolved against it).
class SequencePrompts : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hrg-prompts-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "pictures");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::expected<SequenceConfig, config_file::ConfigError> Parse(const std::string& prompts) {
    return ParseSequenceConfig(kHead + prompts, dir_ / "sequence-q.toml");
  }
  void Write(const fs::path& relative, std::size_t bytes) {
    std::ofstream(dir_ / relative, std::ios::binary) << std::string(bytes, 'x');
  }
  fs::path dir_;
};

TEST_F(SequencePrompts, EachIsAskedWhereItSaysInFileOrder) {
  Write("pictures/lid.png", 100);
  auto sequence = Parse(R"(
[[prompts]]
id = "mount"
at = "start"
text = "Mount the unit."

[[prompts]]
id = "cable"
at = "before_run"
run = 2
text = "Swap the cable."
image = "pictures/lid.png"

[[prompts]]
id = "lid"
at = "start"
text = "Close the lid."

[[prompts]]
id = "remove"
at = "end"
text = "Take the unit off."
)");
  ASSERT_TRUE(sequence) << sequence.error().ToString();
  ASSERT_EQ(sequence->prompts.size(), 4u);
  const auto start = sequence->PromptsAt(PromptPoint::kStart);
  ASSERT_EQ(start.size(), 2u);
  EXPECT_EQ(start[0]->id, "mount");
  EXPECT_EQ(start[1]->id, "lid");
  EXPECT_TRUE(sequence->PromptsAt(PromptPoint::kBeforeRun, 1).empty());
  const auto before_two = sequence->PromptsAt(PromptPoint::kBeforeRun, 2);
  ASSERT_EQ(before_two.size(), 1u);
  EXPECT_EQ(before_two[0]->Where(), "before run 2");
  EXPECT_EQ(before_two[0]->image, "pictures/lid.png");
  EXPECT_EQ(before_two[0]->image_file, dir_ / "pictures/lid.png");
  // SHA-256 of 100 × 'x' (sha256sum), so the record can say which image was shown.
  EXPECT_EQ(before_two[0]->image_sha256,
            "09ecb6ebc8bcefc733f6f2ec44f791abeed6a99edf0cc31519637898aebd52d8");
  EXPECT_EQ(sequence->PromptsAt(PromptPoint::kEnd).front()->Where(), "end");
  EXPECT_EQ(sequence->PromptsAt(PromptPoint::kStart).front()->Where(), "start");
}

TEST_F(SequencePrompts, NoPromptsIsTheDefault) {
  auto sequence = Parse("");
  ASSERT_TRUE(sequence) << sequence.error().ToString();
  EXPECT_TRUE(sequence->prompts.empty());
}

struct Refusal {
  std::string prompts;
  std::size_t line;
  std::string key;
  std::string message_part;
};

TEST_F(SequencePrompts, EveryMistakeIsRefusedNamingItsLineAndKey) {
  Write("big.png", 256 * 1024 + 1);
  Write("notes.txt", 10);
  fs::create_directories(dir_.parent_path() / "outside");
  // kHead has 15 lines: the first prompt's table starts on line 17.
  const Refusal refusals[] = {
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\ntext = \"x\"\n[[prompts]]\nid = \"a\"\n"
       "at = \"end\"\ntext = \"y\"\n",
       22, "prompts[1].id", "repeated"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"before_run\"\ntext = \"x\"\n", 17, "prompts[0].run",
       "missing"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"before_run\"\nrun = 3\ntext = \"x\"\n", 20,
       "prompts[0].run", "out of range"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\nrun = 1\ntext = \"x\"\n", 20, "prompts[0].run",
       "only with at = \"before_run\""},
      {"\n[[prompts]]\nid = \"a\"\nat = \"soon\"\ntext = \"x\"\n", 19, "prompts[0].at", "soon"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\n", 17, "prompts[0].text", "missing"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\ntext = \"x\"\nimage = \"../outside/p.png\"\n",
       21, "prompts[0].image", "without \"..\""},
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\ntext = \"x\"\nimage = \"/etc/passwd\"\n", 21,
       "prompts[0].image", "relative"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\ntext = \"x\"\nimage = \"notes.txt\"\n", 21,
       "prompts[0].image", ".png"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\ntext = \"x\"\nimage = \"gone.png\"\n", 21,
       "prompts[0].image", "no such file"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\ntext = \"x\"\nimage = \"big.png\"\n", 21,
       "prompts[0].image", "at most 262144"},
      {"\n[[prompts]]\nid = \"a\"\nat = \"start\"\ntext = \"x\"\nsound = \"beep\"\n", 21,
       "prompts[0].sound", "unknown"},
  };
  for (const Refusal& r : refusals) {
    auto sequence = Parse(r.prompts);
    ASSERT_FALSE(sequence) << r.prompts;
    const config_file::ConfigError& e = sequence.error();
    EXPECT_EQ(e.file, dir_ / "sequence-q.toml") << e.ToString();
    EXPECT_EQ(e.line, r.line) << e.ToString();
    EXPECT_EQ(e.key, r.key) << e.ToString();
    EXPECT_NE(e.ToString().find(r.message_part), std::string::npos) << e.ToString();
  }
}

TEST_F(SequencePrompts, AtMost64) {
  std::string many;
  for (int i = 0; i < 65; ++i)
    many += "\n[[prompts]]\nid = \"p" + std::to_string(i) + "\"\nat = \"end\"\ntext = \"x\"\n";
  auto sequence = Parse(many);
  ASSERT_FALSE(sequence);
  EXPECT_EQ(sequence.error().key, "prompts");
  EXPECT_NE(sequence.error().message.find("at most 64"), std::string::npos)
      << sequence.error().ToString();
}

}  // namespace
}  // namespace hrgbench::bench
