// session.json writer: the typed fields win, everything else in `document` is written back as is.

#include <cmath>
#include <set>
#include <string>

#include "hrgbench/session/json_depth.hpp"
#include "hrgbench/session/session.hpp"
#include "name_field.hpp"
#include "run_file_path.hpp"

namespace hrgbench::session {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The existing entry for `id` in the document's runs, so keys the bench added to a run survive.
json ExistingRunObject(const json& document, int id) {
  const auto runs = document.find("runs");
  if (runs == document.end() || !runs->is_array()) return json::object();
  for (const json& item : *runs) {
    if (!item.is_object()) continue;
    const auto item_id = item.find("id");
    if (item_id != item.end() && item_id->is_number_integer() &&
        item_id->get<std::int64_t>() == id) {
      return item;
    }
  }
  return json::object();
}

}  // namespace

std::expected<void, SessionError> WriteSessionJson(const fs::path& dir, const Session& session) {
  const fs::path file = dir / "session.json";
  auto fail = [&file](std::string field, std::string message) {
    return std::unexpected(SessionError{file, 0, std::move(field), std::move(message)});
  };
  if (!session.document.is_null() && !session.document.is_object()) {
    return fail("",
                std::string("document must be a JSON object, got ") + session.document.type_name());
  }
  if (!std::isfinite(session.sample_rate_hz) || !(session.sample_rate_hz > 0.0)) {
    return fail("sample_rate_hz",
                "must be finite and positive, got " + std::to_string(session.sample_rate_hz));
  }
  if (const auto problem = internal::NameFieldProblem(session.serial)) {
    return fail("unit.serial", "string " + *problem);
  }
  if (session.runs.size() > kMaxSessionRuns) {
    return fail("runs", std::to_string(session.runs.size()) + " runs (at most " +
                            std::to_string(kMaxSessionRuns) + ")");
  }
  std::set<int> ids;
  for (std::size_t i = 0; i < session.runs.size(); ++i) {
    const RunEntry& run = session.runs[i];
    const std::string path = "runs[" + std::to_string(i) + "]";
    if (run.id < 1) return fail(path + ".id", "run id must be >= 1, got " + std::to_string(run.id));
    if (!ids.insert(run.id).second) {
      return fail(path + ".id", "duplicate run id " + std::to_string(run.id));
    }
    if (const auto problem = internal::RunFilePathProblem(run.file)) {
      return fail(path + ".file", *problem);
    }
    if (const auto problem = internal::NameFieldProblem(run.file)) {
      return fail(path + ".file", "string " + *problem);
    }
    if (const auto problem = internal::NameFieldProblem(run.status)) {
      return fail(path + ".status", "string " + *problem);
    }
    if (!std::isfinite(run.omega_rad_s)) {
      return fail(path + ".omega_rad_s", "non-finite " + std::to_string(run.omega_rad_s));
    }
  }

  std::string text;
  try {
    json doc = session.document.is_null() ? json::object() : session.document;
    doc["format"] = kFormatName;
    doc["version"] = kFormatVersion;
    if (!doc.contains("unit") || !doc["unit"].is_object()) doc["unit"] = json::object();
    doc["unit"]["serial"] = session.serial;
    doc["sample_rate_hz"] = session.sample_rate_hz;
    // Always stated: a record that does not say which way y2 and y4 point can be read wrong
    // without any misfit showing (estimator/iq_convention.hpp).
    if (!doc.contains("electronics") || !doc["electronics"].is_object())
      doc["electronics"] = json::object();
    doc["electronics"]["iq_convention"] =
        std::string(estimator::IqConventionName(session.iq_convention));
    json runs = json::array();
    for (const RunEntry& run : session.runs) {
      json item = ExistingRunObject(session.document, run.id);
      item["id"] = run.id;
      item["file"] = run.file;
      item["omega_rad_s"] = run.omega_rad_s;
      item["status"] = run.status;
      runs.push_back(std::move(item));
    }
    doc["runs"] = std::move(runs);
    text = doc.dump(2) + "\n";
  } catch (const json::exception& e) {
    // dump() throws on strings that are not valid UTF-8.
    return fail("", e.what());
  }

  // The reader's bounds, checked on the text it would read.
  if (text.size() > kMaxSessionJsonBytes) {
    return fail("", "session.json would be " + std::to_string(text.size()) + " bytes (at most " +
                        std::to_string(kMaxSessionJsonBytes) + ")");
  }
  if (const auto excess = FindJsonDepthExcess(text, kMaxSessionJsonDepth)) {
    return fail("", "document nested deeper than " + std::to_string(kMaxSessionJsonDepth) +
                        " levels of arrays and objects");
  }
  if (auto created = CreateDirectoriesDurably(dir); !created) return created;
  return WriteFileAtomic(file, text);
}

}  // namespace hrgbench::session
