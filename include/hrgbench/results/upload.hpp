#pragma once
// Uploading closed sessions: what hrg-bench does after every session (and resume), and what
// hrg-results import/sync do for folders.
//
// The session folder is the source of truth and is complete before anything here runs. An upload
// that fails (no server, wrong credentials, database locked or unwritable, a newer schema) never
// changes the session's outcome: the failure is a value, and MarkUpload records it in session.json
// as "results": {"uploaded": false, "url": ..., "reason": ..., "utc": ...} (true and no reason once
// stored), an atomic rewrite that touches nothing else. The mark is left out of the content hash
// (session_record.hpp), so marking never makes a session look changed.
//
// Threads: each call opens its own connection; calls on different sessions may run concurrently.
// Never throws (except std::bad_alloc).

#include <expected>
#include <filesystem>
#include <string>
#include <vector>

#include "hrgbench/results/results_store.hpp"

namespace hrgbench::results {

struct UploadOutcome {
  bool uploaded = false;
  ImportStatus status = ImportStatus::kUnchanged;  // when uploaded
  std::string reason;                              // when not
};

// Reads `dir` and imports it into `store`.
UploadOutcome UploadSession(ResultsStore& store, const std::filesystem::path& dir,
                            const ImportProbe& probe = {});
// Opens `url` (per call: a station's session end) and uploads; a store that cannot be opened is a
// reason like any other.
UploadOutcome UploadSession(const std::string& url, const std::filesystem::path& dir);

// Writes the "results" mark into `dir`/session.json (see above). Error: the file cannot be read or
// rewritten (message names it).
std::expected<void, std::string> MarkUpload(const std::filesystem::path& dir,
                                            const std::string& url, const UploadOutcome& outcome);

// Every session folder under `root` (the directories that hold a session.json, at most `max_depth`
// levels down, symbolic links not followed), sorted by path.
std::vector<std::filesystem::path> FindSessionDirs(const std::filesystem::path& root,
                                                   int max_depth = 4);

}  // namespace hrgbench::results
