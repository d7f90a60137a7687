// session.json reader. All keys are checked before any CSV is opened, so a bad session.json is
// reported as such even when run files are missing too.

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "hrgbench/session/json_depth.hpp"
#include "hrgbench/session/session.hpp"
#include "json_lines.hpp"
#include "name_field.hpp"
#include "run_file_path.hpp"
#include "session_text.hpp"
#include "whole_file.hpp"

namespace hrgbench::session {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::size_t kMaxShown = 60;

std::string Join(std::string_view parent, std::string_view key) {
  return parent.empty() ? std::string(key) : std::string(parent) + "." + std::string(key);
}

// "string \"abc\"", "number 1.5", ... for messages.
std::string Describe(const json& value) {
  if (value.is_null()) return "null";
  std::string text = value.dump();
  if (text.size() > kMaxShown) text = text.substr(0, kMaxShown) + "...";
  return std::string(value.type_name()) + " " + text;
}

// Validates the parsed document against the text it came from, so every error can carry a line.
class Checker {
 public:
  Checker(std::string_view text, fs::path file) : text_(text), file_(std::move(file)) {}

  // Error about the value at `path`; when it does not exist, at the line of `fallback_path`.
  std::unexpected<SessionError> Fail(const std::string& path, std::string message,
                                     const std::string& fallback_path = "") const {
    std::size_t line = internal::JsonValueLine(text_, path);
    if (line == 0) line = internal::JsonValueLine(text_, fallback_path);
    return std::unexpected(SessionError{file_, line, path, std::move(message)});
  }

  std::expected<const json*, SessionError> Get(const json& object, const std::string& object_path,
                                               const char* key) const {
    const auto it = object.find(key);
    if (it == object.end()) {
      return Fail(Join(object_path, key), std::string("missing key '") + key + "'", object_path);
    }
    return &*it;
  }

  std::expected<const json*, SessionError> GetObject(const json& object,
                                                     const std::string& object_path,
                                                     const char* key) const {
    auto value = Get(object, object_path, key);
    if (value && !(*value)->is_object()) {
      return Fail(Join(object_path, key), "expected an object, got " + Describe(**value));
    }
    return value;
  }

  std::expected<std::string, SessionError> GetString(const json& object,
                                                     const std::string& object_path,
                                                     const char* key) const {
    auto value = Get(object, object_path, key);
    if (!value) return std::unexpected(value.error());
    if (!(*value)->is_string()) {
      return Fail(Join(object_path, key), "expected a string, got " + Describe(**value));
    }
    return (*value)->get<std::string>();
  }

  // A string under the name rule (name_field.hpp).
  std::expected<std::string, SessionError> GetName(const json& object,
                                                   const std::string& object_path,
                                                   const char* key) const {
    auto value = GetString(object, object_path, key);
    if (!value) return value;
    if (const auto problem = internal::NameFieldProblem(*value)) {
      return Fail(Join(object_path, key), "string " + *problem + ": " + Describe(object.at(key)));
    }
    return value;
  }

  std::expected<int, SessionError> GetInt(const json& object, const std::string& object_path,
                                          const char* key) const {
    auto value = Get(object, object_path, key);
    if (!value) return std::unexpected(value.error());
    const json& v = **value;
    const std::string path = Join(object_path, key);
    if (!v.is_number_integer()) return Fail(path, "expected an integer, got " + Describe(v));
    const bool in_range =
        v.is_number_unsigned()
            ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(INT_MAX)
            : v.get<std::int64_t>() >= INT_MIN && v.get<std::int64_t>() <= INT_MAX;
    if (!in_range) return Fail(path, "integer out of range: " + v.dump());
    return v.get<int>();
  }

  std::expected<double, SessionError> GetFinite(const json& object, const std::string& object_path,
                                                const char* key) const {
    auto value = Get(object, object_path, key);
    if (!value) return std::unexpected(value.error());
    const json& v = **value;
    const std::string path = Join(object_path, key);
    if (!v.is_number()) return Fail(path, "expected a number, got " + Describe(v));
    const double number = v.get<double>();
    // nlohmann turns an overflowing literal such as 1e999 into infinity.
    if (!std::isfinite(number)) return Fail(path, "non-finite number " + v.dump());
    return number;
  }

 private:
  std::string_view text_;
  fs::path file_;
};

}  // namespace

namespace internal {

std::vector<std::string> RunStatusWarnings(const std::vector<RunEntry>& runs, bool plan_cut_short) {
  std::vector<std::string> warnings;
  for (const RunEntry& entry : runs) {
    if (plan_cut_short && entry.status == "planned") continue;
    if (entry.status != "complete")
      warnings.push_back("run " + std::to_string(entry.id) + " skipped: status '" + entry.status +
                         "'");
  }
  return warnings;
}

std::expected<Session, SessionError> ReadSessionJson(const std::string& text,
                                                     const fs::path& file) {
  Session session;
  // Before the parser: it recurses once per level (see json_depth.hpp).
  if (const auto excess = FindJsonDepthExcess(text, kMaxSessionJsonDepth)) {
    return std::unexpected(
        SessionError{file, excess->line, "",
                     "nested deeper than " + std::to_string(kMaxSessionJsonDepth) +
                         " levels of arrays and objects (level " + std::to_string(excess->depth) +
                         " opens on this line); a session.json is under 10 deep"});
  }
  // A key twice in one object: nlohmann keeps the last silently, so the file would say two things
  // and be read as one. The parser's callback sees every key; the first repeat is refused by
  // field (the keys of the objects it is in, dotted) and line.
  struct DuplicateKey {
    std::string field;
    std::string key;
    std::size_t occurrence;  // the repeat is this key name's n-th use as a key in the file
  };
  struct Level {
    std::vector<std::string> keys;
    std::string last;
  };
  std::vector<Level> levels;
  std::map<std::string, std::size_t> uses;
  const auto find_repeats = [&](int /*depth*/, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) {
      levels.emplace_back();
    } else if (event == json::parse_event_t::object_end && !levels.empty()) {
      levels.pop_back();
    } else if (event == json::parse_event_t::key && !levels.empty()) {
      const std::string key = parsed.get<std::string>();
      const std::size_t use = ++uses[key];
      Level& level = levels.back();
      if (std::find(level.keys.begin(), level.keys.end(), key) != level.keys.end()) {
        std::string field;
        for (std::size_t i = 0; i + 1 < levels.size(); ++i) field += levels[i].last + ".";
        throw DuplicateKey{field + key, key, use};
      }
      level.keys.push_back(key);
      level.last = key;
    }
    return true;
  };
  try {
    session.document = json::parse(text, find_repeats);
  } catch (const DuplicateKey& repeat) {
    // The line of the key's n-th use ("key" followed by a colon).
    std::size_t line = 0, seen = 0;
    const std::string quoted = "\"" + repeat.key + "\"";
    for (std::size_t at = text.find(quoted); at != std::string::npos;
         at = text.find(quoted, at + 1)) {
      const std::size_t after = text.find_first_not_of(" \t\r\n", at + quoted.size());
      if (after == std::string::npos || text[after] != ':') continue;
      if (++seen == repeat.occurrence) {
        line = internal::LineOfOffset(text, at);
        break;
      }
    }
    return std::unexpected(
        SessionError{file, line, repeat.field,
                     "duplicate key '" + repeat.key +
                         "': a key appears once in an object (which value is meant?)"});
  } catch (const json::parse_error& e) {
    // e.byte is 1-based and points at the character that broke the parse.
    std::string message = e.what();
    if (const auto bracket = message.find("] "); bracket != std::string::npos) {
      message = message.substr(bracket + 2);
    }
    return std::unexpected(
        SessionError{file, internal::LineOfOffset(text, e.byte > 0 ? e.byte - 1 : 0), "", message});
  } catch (const json::out_of_range& e) {
    // A number literal too large for a double ("1e999"): the message quotes it, but has no
    // position.
    std::string message = e.what();
    if (const auto bracket = message.find("] "); bracket != std::string::npos) {
      message = message.substr(bracket + 2);
    }
    SessionError error{file, 0, "", message};
    const auto quote = message.find('\'');
    if (quote != std::string::npos && message.back() == '\'') {
      const std::string token = message.substr(quote + 1, message.size() - quote - 2);
      if (const auto hit = internal::FindJsonScalar(text, token)) {
        error.line = hit->line;
        error.field = hit->path;
      }
    }
    return std::unexpected(std::move(error));
  }
  const json& doc = session.document;
  const Checker check(text, file);
  if (!doc.is_object()) return check.Fail("", "expected an object, got " + Describe(doc));

  const auto format = check.GetString(doc, "", "format");
  if (!format) return std::unexpected(format.error());
  if (*format != kFormatName) {
    return check.Fail(
        "format", "unknown format '" + *format + "' (expected '" + std::string(kFormatName) + "')");
  }
  const auto version = check.GetInt(doc, "", "version");
  if (!version) return std::unexpected(version.error());
  if (*version != kFormatVersion) {
    return check.Fail("version", "unsupported version " + std::to_string(*version) +
                                     " (this reader reads version " +
                                     std::to_string(kFormatVersion) + ")");
  }
  const auto unit = check.GetObject(doc, "", "unit");
  if (!unit) return std::unexpected(unit.error());
  const auto serial = check.GetName(**unit, "unit", "serial");
  if (!serial) return std::unexpected(serial.error());
  session.serial = *serial;
  const auto rate = check.GetFinite(doc, "", "sample_rate_hz");
  if (!rate) return std::unexpected(rate.error());
  if (!(*rate > 0.0)) {
    return check.Fail("sample_rate_hz", "must be positive, got " + doc["sample_rate_hz"].dump());
  }
  session.sample_rate_hz = *rate;

  // electronics.iq_convention: optional (sessions before it was recorded are the model's), but a
  // value this reader does not know is an error: guessing would flip signs silently.
  const auto electronics = doc.find("electronics");
  const json* convention = nullptr;
  if (electronics != doc.end() && electronics->is_object()) {
    if (const auto it = electronics->find("iq_convention"); it != electronics->end())
      convention = &*it;
  }
  if (convention == nullptr) {
    session.notes.push_back(
        "session.json has no electronics.iq_convention (recorded before the convention was "
        "stated): read as the model's 'minus-sine' (y2 = -2*LPF[s*sin])");
  } else {
    const auto parsed = convention->is_string()
                            ? estimator::ParseIqConvention(convention->get<std::string>())
                            : std::nullopt;
    if (!parsed) {
      return check.Fail("electronics.iq_convention",
                        "expected \"minus-sine\" or \"plus-sine\", got " + Describe(*convention));
    }
    session.iq_convention = *parsed;
    if (*parsed == estimator::IqConvention::kPlusSine) {
      session.notes.push_back(
          "electronics.iq_convention = 'plus-sine': each channel's complex sample conjugated (y2 "
          "and y4 negated) into the model's convention before estimating");
    }
  }

  const auto runs = check.Get(doc, "", "runs");
  if (!runs) return std::unexpected(runs.error());
  if (!(*runs)->is_array()) return check.Fail("runs", "expected an array, got " + Describe(**runs));
  if ((*runs)->size() > kMaxSessionRuns) {
    return check.Fail("runs", std::to_string((*runs)->size()) + " runs (at most " +
                                  std::to_string(kMaxSessionRuns) + ")");
  }
  std::map<int, std::size_t> index_of_id;
  for (std::size_t i = 0; i < (*runs)->size(); ++i) {
    const json& item = (**runs)[i];
    const std::string path = "runs[" + std::to_string(i) + "]";
    if (!item.is_object()) return check.Fail(path, "expected an object, got " + Describe(item));
    RunEntry entry;
    const auto id = check.GetInt(item, path, "id");
    if (!id) return std::unexpected(id.error());
    if (*id < 1) return check.Fail(path + ".id", "run id must be >= 1, got " + std::to_string(*id));
    if (const auto [it, inserted] = index_of_id.emplace(*id, i); !inserted) {
      return check.Fail(path + ".id", "duplicate run id " + std::to_string(*id) + " (also runs[" +
                                          std::to_string(it->second) + "].id)");
    }
    entry.id = *id;
    const auto run_file = check.GetName(item, path, "file");
    if (!run_file) return std::unexpected(run_file.error());
    if (const auto problem = internal::RunFilePathProblem(*run_file)) {
      return check.Fail(path + ".file", *problem);
    }
    entry.file = *run_file;
    const auto omega = check.GetFinite(item, path, "omega_rad_s");
    if (!omega) return std::unexpected(omega.error());
    entry.omega_rad_s = *omega;
    // How well Ω is known, when the bench recorded it: runs[].end.omega_std_error_rad_s, a number
    // >= 0 or null (not measured).
    if (const auto end = item.find("end"); end != item.end() && end->is_object()) {
      if (const auto sd = end->find("omega_std_error_rad_s"); sd != end->end() && !sd->is_null()) {
        const std::string sd_path = path + ".end.omega_std_error_rad_s";
        if (!sd->is_number()) return check.Fail(sd_path, "expected a number, got " + Describe(*sd));
        const double value = sd->get<double>();
        if (!std::isfinite(value) || value < 0.0)
          return check.Fail(sd_path, "expected a finite number >= 0, got " + sd->dump());
        entry.omega_std_rad_s = value;
      }
    }
    const auto status = check.GetName(item, path, "status");
    if (!status) return std::unexpected(status.error());
    entry.status = *status;
    session.runs.push_back(std::move(entry));
  }
  // A plan the sequence's [adaptive] cut short (outcome.ended_early): its runs left "planned" were
  // not needed, and the record says so; no warning for each.
  const auto outcome = doc.find("outcome");
  const bool ended_early =
      outcome != doc.end() && outcome->is_object() && outcome->contains("ended_early");
  session.warnings = RunStatusWarnings(session.runs, ended_early);
  return session;
}

}  // namespace internal

std::expected<void, SessionError> ReadEachRun(const fs::path& dir, const Session& session,
                                              const ReadOptions& options,
                                              const RunSamplesSink& on_run) {
  for (const RunEntry& entry : session.runs) {
    if (entry.status != "complete") continue;  // warned by ReadSessionJson
    auto samples = ReadRunCsv(dir / entry.file, options.min_samples_per_run, options.extra_columns);
    if (!samples) return std::unexpected(samples.error());
    if (auto taken = on_run(entry, std::move(*samples)); !taken) return taken;
  }
  return {};
}

std::expected<Session, SessionError> ReadSession(const fs::path& dir, const ReadOptions& options) {
  const fs::path json_file = dir / "session.json";
  try {
    // A plain file given as the directory: say so, rather than "cannot open dir/session.json".
    std::error_code ec;
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
      return std::unexpected(
          SessionError{dir, 0, "", "not a directory (a session is a directory)"});
    }
    const auto text = internal::ReadWholeFile(json_file, kMaxSessionJsonBytes);
    if (!text) return std::unexpected(text.error());
    auto session = internal::ReadSessionJson(*text, json_file);
    if (!session) return session;
    if (options.plan_cut_short)
      session->warnings = internal::RunStatusWarnings(session->runs, true);

    if (!options.load_samples) return session;
    Session& loaded = *session;
    const auto keep = [&loaded](const RunEntry& entry,
                                RunSamples&& samples) -> std::expected<void, SessionError> {
      loaded.loaded_run_ids.push_back(entry.id);
      loaded.loaded_samples.push_back(std::move(samples));
      return {};
    };
    if (auto read = ReadEachRun(dir, loaded, options, keep); !read)
      return std::unexpected(read.error());
    return session;
  } catch (const json::exception& e) {
    // Not expected after the checks above; kept so that no exception crosses the API.
    return std::unexpected(SessionError{json_file, 0, "", e.what()});
  }
}

}  // namespace hrgbench::session
