#include "app/session_upload.hpp"

#include <spdlog/spdlog.h>

#include "hrgbench/results/upload.hpp"

namespace hrgbench::app {

void UploadClosedSession(const std::string& url, const std::filesystem::path& dir) noexcept {
  std::error_code ec;
  if (url.empty() || dir.empty() || !std::filesystem::exists(dir / "session.json", ec)) return;
  try {
    const results::UploadOutcome outcome = results::UploadSession(url, dir);
    if (outcome.uploaded) {
      spdlog::info("results: session {} in {}", results::ToString(outcome.status), url);
    } else {
      spdlog::warn("results: not uploaded ({}); `hrg-results sync` uploads it later",
                   outcome.reason);
    }
    if (auto marked = results::MarkUpload(dir, url, outcome); !marked)
      spdlog::error("results: {}", marked.error());
  } catch (const std::exception& error) {
    spdlog::error("results: not uploaded: {}", error.what());
  } catch (...) {
    spdlog::error("results: not uploaded: unknown failure");
  }
}

}  // namespace hrgbench::app
