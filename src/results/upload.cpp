#include "hrgbench/results/upload.hpp"

#include <algorithm>
#include <ctime>
#include <nlohmann/json.hpp>

#include "hrgbench/session/session.hpp"

namespace hrgbench::results {
namespace fs = std::filesystem;

UploadOutcome UploadSession(ResultsStore& store, const fs::path& dir, const ImportProbe& probe) {
  UploadOutcome outcome;
  auto record = ReadSessionRow(dir);
  if (!record) {
    outcome.reason = record.error();
    return outcome;
  }
  auto status = store.Import(*record, probe);
  if (!status) {
    outcome.reason = status.error().message;
    return outcome;
  }
  outcome.uploaded = true;
  outcome.status = *status;
  return outcome;
}

UploadOutcome UploadSession(const std::string& url, const fs::path& dir) {
  auto store = ResultsStore::Open(url);
  if (!store) return UploadOutcome{false, ImportStatus::kUnchanged, store.error().message};
  return UploadSession(**store, dir);
}

std::expected<void, std::string> MarkUpload(const fs::path& dir, const std::string& url,
                                            const UploadOutcome& outcome) {
  session::ReadOptions options;
  options.load_samples = false;
  auto loaded = session::ReadSession(dir, options);
  if (!loaded) return std::unexpected("upload mark not written: " + loaded.error().ToString());
  nlohmann::json mark;
  mark["uploaded"] = outcome.uploaded;
  mark["url"] = url;
  if (!outcome.uploaded) mark["reason"] = outcome.reason;
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &utc);
  mark["utc"] = stamp;
  nlohmann::json document = std::move(loaded->document);
  document["results"] = std::move(mark);
  std::string text;
  try {
    text = document.dump(2) + "\n";
  } catch (const nlohmann::json::exception&) {  // a reason that is not valid UTF-8
    document["results"]["reason"] = "(reason not representable as UTF-8)";
    text = document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  }
  if (auto written = session::WriteFileAtomic(dir / "session.json", text); !written)
    return std::unexpected("upload mark not written: " + written.error().ToString());
  return {};
}

std::vector<fs::path> FindSessionDirs(const fs::path& root, int max_depth) {
  std::vector<fs::path> out;
  std::error_code ec;
  if (fs::is_regular_file(root / "session.json", ec)) out.push_back(root);
  fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec);
  for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it.depth() >= max_depth) it.disable_recursion_pending();
    std::error_code entry_ec;
    if (it->is_directory(entry_ec) && !it->is_symlink(entry_ec) &&
        fs::is_regular_file(it->path() / "session.json", entry_ec)) {
      out.push_back(it->path());
      it.disable_recursion_pending();  // a session's own folders hold no sessions
    }
  }
  std::ranges::sort(out);
  return out;
}

}  // namespace hrgbench::results
