#pragma once
// Where `hrg-bench run|resume` gets the answers to its sequence's operator prompts
// (bench/sequencer/operator_prompts.hpp), as `--prompts` says:
//   terminal  the prompt on stderr, the answer typed on stdin (Enter: confirm; "a": abort)
//   fd:N      JSON lines on file descriptor N, one per answer: {"id", "answer": "confirm" |
//             "abort", "by"} (the panel's pipe: panel/session_process.hpp)
//   confirm   every prompt confirmed at once, recorded as answered by nobody ("auto"): a
//             simulated station's script, or a fixture no person tends
// Not given: the terminal when stdin is one; else a sequence with prompts is refused before
// anything starts (exit 4), so a session never waits for an answer nobody can give.
//
// Bounds: an answer line is at most kMaxAnswerBytes (longer ones are dropped whole, said on
// stderr). Not thread-safe (the sequencer's thread only).

#include <cstddef>
#include <expected>
#include <memory>
#include <string>

#include "hrgbench/bench/sequencer/operator_prompts.hpp"
#include "hrgbench/config/sequence_config.hpp"

namespace hrgbench::app {

inline constexpr std::size_t kMaxAnswerBytes = 4096;

// The source `mode` names for `sequence` (nullptr when the sequence has no prompts: nothing to
// answer); `operator_id` is who answers on a terminal. The error says what to do instead.
std::expected<std::unique_ptr<bench::PromptAnswers>, std::string> OpenPromptAnswers(
    const std::string& mode, const bench::SequenceConfig& sequence, const std::string& operator_id);

}  // namespace hrgbench::app
