#pragma once
// Where a session's operator prompts (the sequence's [[prompts]]) are answered: the panel (its
// dialog), a terminal, or nobody (`--prompts confirm`, said in the record as "auto"). The
// sequencer asks; the app gives it the source that fits how it was started (src/app).
//
// The sequencer calls Show once per prompt, then Wait again and again with a short wait until an
// answer comes: between the calls it keeps the table's heartbeat, shows the table's rate and sees
// an Abort or Ctrl-C, so a source never has to know about any of that. Called on the sequencer's
// thread only.

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

namespace hrgbench::bench {

struct PromptRequest {
  std::string id;
  std::string at;  // "start", "before run 3", "end"
  std::string text;
  std::filesystem::path image_file;  // empty: none
  std::string image_sha256;
};

struct PromptReply {
  bool confirmed = false;  // false: the operator chose to abort the session
  std::string by;          // who answered (an operator id); the source's best knowledge
  std::string how;         // "panel", "terminal", "auto"
};

class PromptAnswers {
 public:
  virtual ~PromptAnswers() = default;
  virtual void Show(const PromptRequest& prompt) = 0;
  // The answer to the prompt last shown, waiting up to `wait` for it; nullopt: none yet. A source
  // that cannot answer any more (its input closed) answers abort, saying why in `by`.
  virtual std::optional<PromptReply> Wait(std::chrono::milliseconds wait) = 0;
};

}  // namespace hrgbench::bench
