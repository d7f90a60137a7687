#pragma once
// hrg-bench's one call after a session is closed (and its report written): upload the folder to
// the station's results database and record in session.json whether that worked. Nothing here can
// change the session's outcome or exit code: every failure is logged and marked, never thrown.

#include <filesystem>
#include <string>

namespace hrgbench::app {

// `url` empty: no database configured, nothing done. Otherwise uploads `dir` and writes the
// "results" mark (results/upload.hpp). Logs one line either way. Never throws.
void UploadClosedSession(const std::string& url, const std::filesystem::path& dir) noexcept;

}  // namespace hrgbench::app
