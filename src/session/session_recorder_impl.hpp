#pragma once
// Internal: SessionRecorder's state. The record lives in `session` (the estimator format's typed
// fields plus the whole document); every change is made there and written with
// session::WriteSessionJson, so session.json always goes through temp + fsync + rename.

#include <expected>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hrgbench/session/candump_log.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_recorder.hpp"
#include "run_csv_stream.hpp"

namespace hrgbench::bench {

class SessionRecorder::Impl {
 public:
  std::filesystem::path dir;
  RecorderOptions options;
  session::Session session;
  std::vector<PlannedRun> plans;  // parallel to session.runs
  std::optional<CandumpLogWriter> can_log;
  std::optional<internal::RunCsvStream> stream;
  std::optional<int> open_run;
  std::optional<std::size_t> open_prompt;  // index in document["prompts"]
  // Runs closed by an I/O failure, with the reason, for Close to record them as aborted.
  std::vector<std::pair<int, std::string>> failed_runs;
  bool closed = false;

  // Index of run `id` in session.runs (and plans, and document["runs"]), or -1.
  int IndexOf(int run_id) const;
  nlohmann::json& RunObject(std::size_t index);  // document["runs"][index]
  std::expected<void, RecordError> WriteJson();
  // <dir>/.reserve: space set aside while the session runs, given back when session.json cannot
  // be written (a full disk), so the record can still say how the session ended. Best effort.
  void Reserve() const;
  bool ReleaseReserve() const;  // true when there was a reserve to give back
  RecordError WrongState(std::string message) const;
  // Renames `from` to `to`, or `to`.2, `to`.3 ... if taken; returns the name relative to `dir`.
  std::expected<std::string, RecordError> MoveAside(const std::filesystem::path& from,
                                                    const std::string& to_relative);
};

}  // namespace hrgbench::bench
