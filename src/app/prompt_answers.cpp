#include "app/prompt_answers.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

namespace hrgbench::app {
namespace {

// Complete lines from a file descriptor, read as they come without blocking longer than asked.
class LineReader {
 public:
  explicit LineReader(int fd) : fd_(fd) {}

  // The next complete line (without its newline), waiting up to `wait` for one; nullopt: none
  // yet. closed() after the input ended.
  std::optional<std::string> Next(std::chrono::milliseconds wait) {
    if (auto line = Take()) return line;
    if (closed_) return std::nullopt;
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(wait.count()));
    if (ready <= 0) return std::nullopt;  // timeout, or EINTR (a signal: the caller checks it)
    char chunk[1024];
    const ssize_t got = ::read(fd_, chunk, sizeof chunk);
    if (got == 0 || (got < 0 && errno != EINTR && errno != EAGAIN)) {
      closed_ = true;
      return std::nullopt;
    }
    if (got > 0) buffer_.append(chunk, static_cast<std::size_t>(got));
    return Take();
  }
  bool closed() const { return closed_; }

 private:
  std::optional<std::string> Take() {
    for (;;) {
      const std::size_t end = buffer_.find('\n');
      if (end == std::string::npos) {
        // A line longer than the bound is dropped up to its end, never kept growing.
        if (buffer_.size() > kMaxAnswerBytes) {
          buffer_.clear();
          skipping_ = true;
        }
        return std::nullopt;
      }
      std::string line = buffer_.substr(0, end);
      buffer_.erase(0, end + 1);
      if (skipping_ || line.size() > kMaxAnswerBytes) {
        skipping_ = false;
        std::fprintf(stderr, "prompts: an answer line longer than %zu bytes was dropped\n",
                     kMaxAnswerBytes);
        continue;
      }
      if (!line.empty() && line.back() == '\r') line.pop_back();
      return line;
    }
  }

  int fd_;
  std::string buffer_;
  bool closed_ = false;
  bool skipping_ = false;
};

class TerminalAnswers final : public bench::PromptAnswers {
 public:
  explicit TerminalAnswers(std::string operator_id)
      : operator_id_(std::move(operator_id)), input_(STDIN_FILENO) {}

  void Show(const bench::PromptRequest& prompt) override {
    std::fprintf(stderr, "\n== operator prompt '%s' (%s) ==\n%s\n", prompt.id.c_str(),
                 prompt.at.c_str(), prompt.text.c_str());
    if (!prompt.image_file.empty())
      std::fprintf(stderr, "(image: %s)\n", prompt.image_file.c_str());
    std::fprintf(stderr,
                 "The table is at zero rate. Enter: done, go on · a + Enter: abort the "
                 "session\n> ");
    std::fflush(stderr);
  }

  std::optional<bench::PromptReply> Wait(std::chrono::milliseconds wait) override {
    std::optional<std::string> line = input_.Next(wait);
    if (!line) {
      if (input_.closed()) return bench::PromptReply{false, "terminal input closed", "terminal"};
      return std::nullopt;
    }
    const std::string_view typed = *line;
    if (typed.empty() || typed == "y" || typed == "c" || typed == "confirm")
      return bench::PromptReply{true, Who(), "terminal"};
    if (typed == "a" || typed == "abort") return bench::PromptReply{false, Who(), "terminal"};
    std::fprintf(stderr, "Enter: done, go on · a + Enter: abort the session\n> ");
    std::fflush(stderr);
    return std::nullopt;
  }

 private:
  // The operator given with --operator, else the login that typed it.
  std::string Who() const {
    if (!operator_id_.empty()) return operator_id_;
    const char* user = std::getenv("USER");
    return user != nullptr ? user : "";
  }
  std::string operator_id_;
  LineReader input_;
};

class PipeAnswers final : public bench::PromptAnswers {
 public:
  explicit PipeAnswers(int fd) : input_(fd) {}

  void Show(const bench::PromptRequest& prompt) override { open_id_ = prompt.id; }

  std::optional<bench::PromptReply> Wait(std::chrono::milliseconds wait) override {
    std::optional<std::string> line = input_.Next(wait);
    if (!line) {
      if (input_.closed())
        return bench::PromptReply{false, "the panel's answer pipe closed", "panel"};
      return std::nullopt;
    }
    const nlohmann::json answer = nlohmann::json::parse(*line, nullptr, false);
    const auto text = [&](const char* key) {
      const auto it = answer.is_object() ? answer.find(key) : answer.end();
      return it != answer.end() && it->is_string() ? it->get<std::string>() : std::string();
    };
    const std::string choice = text("answer");
    if (text("id") != open_id_ || (choice != "confirm" && choice != "abort")) {
      // An answer to an earlier prompt (two browsers) or a malformed one: not this prompt's.
      std::fprintf(stderr, "prompts: answer ignored (open prompt '%s'): %.200s\n", open_id_.c_str(),
                   line->c_str());
      return std::nullopt;
    }
    return bench::PromptReply{choice == "confirm", text("by"), "panel"};
  }

 private:
  LineReader input_;
  std::string open_id_;
};

class AutoConfirm final : public bench::PromptAnswers {
 public:
  void Show(const bench::PromptRequest&) override {}  // the sequencer logs the prompt
  std::optional<bench::PromptReply> Wait(std::chrono::milliseconds) override {
    return bench::PromptReply{true, "", "auto"};
  }
};

}  // namespace

std::expected<std::unique_ptr<bench::PromptAnswers>, std::string> OpenPromptAnswers(
    const std::string& mode, const bench::SequenceConfig& sequence,
    const std::string& operator_id) {
  const std::string usage = "--prompts: expected terminal, confirm or fd:N, got '" + mode + "'";
  std::unique_ptr<bench::PromptAnswers> source;
  if (mode == "terminal") {
    source = std::make_unique<TerminalAnswers>(operator_id);
  } else if (mode == "confirm") {
    source = std::make_unique<AutoConfirm>();
  } else if (mode.starts_with("fd:")) {
    int fd = -1;
    const char* first = mode.data() + 3;
    const char* last = mode.data() + mode.size();
    const auto [end, error] = std::from_chars(first, last, fd);
    if (error != std::errc() || end != last || fd < 0 || first == last)
      return std::unexpected(usage);
    if (::fcntl(fd, F_GETFD) < 0)
      return std::unexpected("--prompts " + mode + ": file descriptor " + std::to_string(fd) +
                             " is not open");
    source = std::make_unique<PipeAnswers>(fd);
  } else if (!mode.empty()) {
    return std::unexpected(usage);
  }
  if (sequence.prompts.empty()) return std::unique_ptr<bench::PromptAnswers>();
  if (source) return source;
  if (::isatty(STDIN_FILENO) == 1) return std::make_unique<TerminalAnswers>(operator_id);
  return std::unexpected(sequence.file.string() + ": " + std::to_string(sequence.prompts.size()) +
                         " operator prompt(s) ([[prompts]]) and no terminal to answer them on: "
                         "run it on a terminal, from the panel, or with --prompts confirm");
}

}  // namespace hrgbench::app
