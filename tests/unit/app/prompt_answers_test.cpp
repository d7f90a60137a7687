// Where hrg-bench's operator prompts are answered (app/prompt_answers.hpp): the panel's pipe of
// JSON lines (an answer to another prompt ignored, a line over the bound dropped whole, a closed
// pipe an abort), and the choice of source (--prompts, or none needed without prompts).

#include "app/prompt_answers.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <string>

namespace hrgbench::app {
namespace {

using namespace std::chrono_literals;

bench::SequenceConfig WithPrompts(std::size_t n) {
  bench::SequenceConfig sequence;
  sequence.file = "bench_configs/sequence-x.toml";
  for (std::size_t i = 0; i < n; ++i) {
    bench::SequencePrompt prompt;
    prompt.id = "p" + std::to_string(i);
    sequence.prompts.push_back(prompt);
  }
  return sequence;
}

class Pipe {
 public:
  Pipe() { EXPECT_EQ(::pipe(fds_), 0); }
  ~Pipe() {
    CloseWrite();
    ::close(fds_[0]);
  }
  int read_fd() const { return fds_[0]; }
  void Write(const std::string& text) {
    EXPECT_EQ(::write(fds_[1], text.data(), text.size()), static_cast<ssize_t>(text.size()));
  }
  void CloseWrite() {
    if (fds_[1] >= 0) ::close(fds_[1]);
    fds_[1] = -1;
  }

 private:
  int fds_[2] = {-1, -1};
};

TEST(PromptAnswers, ThePanelsPipeAnswersTheOpenPromptOnly) {
  Pipe pipe;
  auto source = OpenPromptAnswers("fd:" + std::to_string(pipe.read_fd()), WithPrompts(2), "");
  ASSERT_TRUE(source.has_value()) << source.error();
  ASSERT_NE(*source, nullptr);
  (*source)->Show({"p0", "start", "x", "", ""});
  EXPECT_FALSE((*source)->Wait(10ms).has_value());  // nothing written yet
  pipe.Write(R"({"id":"p1","answer":"confirm","by":"OP-A"})"
             "\n"
             R"({"id":"p0","answer":"maybe","by":"OP-A"})"
             "\n"
             "not json\n");
  pipe.Write(std::string(kMaxAnswerBytes + 10, 'x') + "\n");
  pipe.Write(R"({"id":"p0","answer":"abort","by":"OP-B"})"
             "\n");
  std::optional<bench::PromptReply> reply;
  for (int i = 0; i < 20 && !reply; ++i) reply = (*source)->Wait(50ms);
  ASSERT_TRUE(reply.has_value());
  EXPECT_FALSE(reply->confirmed);
  EXPECT_EQ(reply->by, "OP-B");
  EXPECT_EQ(reply->how, "panel");
  // The pipe closed with a prompt open: nobody can answer any more, so the session stops.
  (*source)->Show({"p1", "end", "y", "", ""});
  pipe.CloseWrite();
  reply.reset();
  for (int i = 0; i < 20 && !reply; ++i) reply = (*source)->Wait(50ms);
  ASSERT_TRUE(reply.has_value());
  EXPECT_FALSE(reply->confirmed);
  EXPECT_EQ(reply->by, "the panel's answer pipe closed");
}

TEST(PromptAnswers, ConfirmAnswersAtOnceAsNobody) {
  auto source = OpenPromptAnswers("confirm", WithPrompts(1), "OP-Z");
  ASSERT_TRUE(source.has_value()) << source.error();
  (*source)->Show({"p0", "start", "x", "", ""});
  const auto reply = (*source)->Wait(0ms);
  ASSERT_TRUE(reply.has_value());
  EXPECT_TRUE(reply->confirmed);
  EXPECT_EQ(reply->by, "");
  EXPECT_EQ(reply->how, "auto");
}

TEST(PromptAnswers, NoSourceIsNeededWithoutPromptsAndABadModeIsRefused) {
  auto none = OpenPromptAnswers("", WithPrompts(0), "");
  ASSERT_TRUE(none.has_value()) << none.error();
  EXPECT_EQ(*none, nullptr);
  for (const char* bad : {"fd:", "fd:x", "fd:-1", "fd:3x", "stdin"}) {
    auto refused = OpenPromptAnswers(bad, WithPrompts(1), "");
    ASSERT_FALSE(refused.has_value()) << bad;
    EXPECT_NE(refused.error().find("expected terminal, confirm or fd:N"), std::string::npos)
        << refused.error();
  }
}

}  // namespace
}  // namespace hrgbench::app
