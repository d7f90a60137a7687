// SessionRecorder::OpenForResume: turn what a dead process left into a session that can go on.

#include <cmath>
#include <string>
#include <system_error>

#include "append_file.hpp"
#include "hrgbench/session/session_record.hpp"
#include "hrgbench/session/session_record_keys.hpp"
#include "hrgbench/session/session_recorder.hpp"
#include "session_document.hpp"
#include "session_recorder_impl.hpp"

namespace hrgbench::bench {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::unexpected<RecordError> BadSession(const fs::path& file, std::string message) {
  return std::unexpected(RecordError{RecordErrorKind::kBadSession, file, std::move(message)});
}

constexpr std::string_view kPartialSuffix = ".csv.partial";

}  // namespace

std::expected<SessionRecorder, RecordError> SessionRecorder::OpenForResume(
    const fs::path& dir, const RecorderOptions& options, const std::string& operator_name) {
  auto read = session::ReadSessionRecord(dir);
  if (!read) return BadSession(read.error().file, read.error().ToString());
  const session::SessionRecord& record = *read;

  auto impl = std::make_unique<Impl>();
  impl->dir = dir;
  impl->options = options;
  // The writer's view of the record: the typed fields it rewrites and the document it keeps.
  impl->session.serial = record.unit_serial;
  impl->session.sample_rate_hz = record.sample_rate_hz;
  impl->session.iq_convention = record.iq_convention;
  impl->session.notes = record.notes;
  for (const session::RunRecord& run : record.runs) {
    session::RunEntry entry;
    entry.id = run.id;
    entry.file = run.file;
    entry.omega_rad_s = run.omega_rad_s;
    entry.status = run.status;
    if (run.end) entry.omega_std_rad_s = run.end->values.omega_std_error_rad_s;
    impl->session.runs.push_back(std::move(entry));
  }
  impl->session.document = record.document;
  json& doc = impl->session.document;
  const fs::path json_file = dir / "session.json";
  if (record.state.empty()) {
    return BadSession(json_file, "no \"state\": not a session written by hrg-bench");
  }
  for (const session::RunRecord& run : record.runs) {
    if (!run.plan) {
      return BadSession(json_file, "run " + std::to_string(run.id) + " has no \"plan\"");
    }
    const bench::PlannedRun& plan = *run.plan;
    for (const double v : {plan.commanded_omega_rad_s, plan.a, plan.b, plan.theta_rad,
                           plan.free_run_s, plan.sample_rate_hz}) {
      if (!std::isfinite(v)) {
        return BadSession(json_file, "run " + std::to_string(run.id) +
                                         ": plan incomplete (a field missing or not a number)");
      }
    }
    impl->plans.push_back(plan);
  }

  // The run the dead process was capturing: an attempt, its streamed data kept for forensics.
  std::error_code ec;
  for (std::size_t i = 0; i < impl->session.runs.size(); ++i) {
    session::RunEntry& entry = impl->session.runs[i];
    if (entry.status != kRunRunning) continue;
    json& object = doc["runs"][i];
    json attempt{{"status", kRunInterrupted}};
    if (object.contains("start")) attempt["start"] = object["start"];
    const fs::path partial = dir / (entry.file + ".partial");
    // A finished CSV with "running" in session.json: the process died between the rename and
    // the session.json write. The data is whole, but its end conditions were never recorded.
    for (const fs::path& from : {partial, dir / entry.file}) {
      if (!fs::exists(from, ec)) continue;
      auto moved = impl->MoveAside(from, entry.file + ".interrupted");
      if (!moved) return std::unexpected(moved.error());
      attempt["file"] = *moved;
    }
    object["attempts"].push_back(std::move(attempt));
    object.erase("start");
    object.erase("end");
    entry.status = kRunInterrupted;
  }
  // Any other .partial (the process died between creating it and recording the run as running).
  for (const fs::directory_entry& file : fs::directory_iterator(dir / "runs", ec)) {
    const std::string name = file.path().filename().string();
    if (name.size() <= kPartialSuffix.size() || !name.ends_with(kPartialSuffix)) continue;
    const std::string stem = name.substr(0, name.size() - std::string_view(".partial").size());
    auto moved = impl->MoveAside(file.path(), "runs/" + stem + ".interrupted");
    if (!moved) return std::unexpected(moved.error());
  }

  const std::string interface_name = record.can_log && !record.can_log->interface_name.empty()
                                         ? record.can_log->interface_name
                                         : "can0";
  if (auto made = internal::MakeDirectoryDurably(dir / "can"); !made) {
    return std::unexpected(made.error());
  }
  CandumpLogOptions log_options;
  log_options.interface_name = interface_name;
  log_options.flush_interval_ns = options.flush_interval_ns;
  log_options.append = true;
  auto log = CandumpLogWriter::Open(dir / "can" / "session.log", log_options);
  if (!log) return std::unexpected(log.error());
  impl->can_log = std::move(*log);

  json resumed = internal::TimeStampNow();
  resumed["previous_state"] = record.state;
  if (!operator_name.empty()) {
    resumed[session::keys::kOperator] = operator_name;
    if (record.operator_name.empty()) doc[session::keys::kOperator] = operator_name;
  }
  if (doc.contains("outcome")) resumed["previous_outcome"] = doc["outcome"];
  // A prompt the process died with open: said so, as a run left running becomes interrupted.
  if (auto prompts = doc.find(session::keys::kPrompts);
      prompts != doc.end() && prompts->is_array()) {
    for (json& prompt : *prompts) {
      if (!prompt.is_object() || prompt.contains(session::keys::kAnswer)) continue;
      prompt[session::keys::kAnswer] = kPromptInterrupted;
      prompt[session::keys::kReason] = "the process ended while it was open";
    }
  }
  doc["resumed_at"].push_back(std::move(resumed));
  doc.erase("outcome");
  doc.erase("ended");
  doc["state"] = "running";
  if (auto written = impl->WriteJson(); !written) return std::unexpected(written.error());
  impl->Reserve();
  return SessionRecorder(std::move(impl));
}

}  // namespace hrgbench::bench
