// SessionRecorder: Create, the run cycle and Close. OpenForResume is in session_resume.cpp.

#include "hrgbench/session/session_recorder.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <system_error>

#include "append_file.hpp"
#include "hrgbench/session/kill_point.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record_keys.hpp"
#include "session_document.hpp"
#include "session_recorder_impl.hpp"

namespace hrgbench::bench {

namespace fs = std::filesystem;
using nlohmann::json;

int SessionRecorder::Impl::IndexOf(int run_id) const {
  for (std::size_t i = 0; i < session.runs.size(); ++i) {
    if (session.runs[i].id == run_id) return static_cast<int>(i);
  }
  return -1;
}

json& SessionRecorder::Impl::RunObject(std::size_t index) {
  return session.document["runs"][index];
}

std::expected<void, RecordError> SessionRecorder::Impl::WriteJson() {
  auto written = session::WriteSessionJson(dir, session);
  if (!written) return std::unexpected(internal::FromSessionError(written.error()));
  return {};
}

namespace {
// Several rewrites of session.json (each a temporary beside the old one) fit in it.
constexpr off_t kReserveBytes = 512 * 1024;
}  // namespace

void SessionRecorder::Impl::Reserve() const {
  const fs::path file = dir / ".reserve";
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return;
  // fallocate reserves real blocks (a sparse file would reserve nothing); ignored where refused.
  (void)::posix_fallocate(fd, 0, kReserveBytes);
  ::close(fd);
}

bool SessionRecorder::Impl::ReleaseReserve() const {
  return ::unlink((dir / ".reserve").c_str()) == 0;
}

RecordError SessionRecorder::Impl::WrongState(std::string message) const {
  return RecordError{RecordErrorKind::kWrongState, dir, std::move(message)};
}

std::expected<std::string, RecordError> SessionRecorder::Impl::MoveAside(
    const fs::path& from, const std::string& to_relative) {
  std::error_code ec;
  std::string name = to_relative;
  for (int k = 2; fs::exists(dir / name, ec); ++k) name = to_relative + "." + std::to_string(k);
  if (auto moved = internal::RenameDurably(from, dir / name); !moved) {
    return std::unexpected(moved.error());
  }
  return name;
}

SessionRecorder::SessionRecorder(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SessionRecorder::SessionRecorder(SessionRecorder&&) noexcept = default;
SessionRecorder& SessionRecorder::operator=(SessionRecorder&&) noexcept = default;
SessionRecorder::~SessionRecorder() {
  if (impl_ && impl_->stream) impl_->stream->Close();
}

std::expected<SessionRecorder, RecordError> SessionRecorder::Create(
    const fs::path& dir, const SessionHeader& header, const RecorderOptions& options) {
  if (const std::string problem = internal::HeaderProblem(header); !problem.empty()) {
    return std::unexpected(RecordError{RecordErrorKind::kInvalidArgument, dir, problem});
  }
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) {
      return std::unexpected(
          RecordError{RecordErrorKind::kIo, dir, "exists and is not a directory"});
    }
    if (!fs::is_empty(dir, ec)) {
      return std::unexpected(
          RecordError{RecordErrorKind::kDirectoryNotEmpty, dir, "session directory is not empty"});
    }
  }
  for (const fs::path& d : {dir, dir / "runs", dir / "can"}) {
    if (auto made = internal::MakeDirectoryDurably(d); !made) return std::unexpected(made.error());
  }
  session::KillPoint("record.dirs");
  // Before session.json: a folder with a session.json always has what resume needs beside it.
  for (const auto& [relative, contents] : header.files_first) {
    const fs::path file = dir / relative;
    if (auto made = session::CreateDirectoriesDurably(file.parent_path()); !made)
      return std::unexpected(internal::FromSessionError(made.error()));
    if (auto written = session::WriteFileAtomic(file, contents); !written)
      return std::unexpected(internal::FromSessionError(written.error()));
  }

  auto impl = std::make_unique<Impl>();
  impl->dir = dir;
  impl->options = options;
  impl->plans = header.runs;
  session::Session& s = impl->session;
  s.serial = header.unit_serial;
  s.sample_rate_hz = header.runs.front().sample_rate_hz;
  json doc = json::object();
  doc["state"] = "running";
  doc["station"] = {{"name", header.station_name}};
  if (!header.operator_name.empty()) doc[session::keys::kOperator] = header.operator_name;
  doc["software"] = {{"version", header.software_version}};
  doc["realtime"] = header.realtime_status;
  doc["config_sha256"] = {{"station", header.config_sha256.station_sha256},
                          {"sequence", header.config_sha256.sequence_sha256},
                          {"limits", header.config_sha256.limits_sha256.empty()
                                         ? json(nullptr)
                                         : json(header.config_sha256.limits_sha256)}};
  doc["started"] = internal::TimeStampNow();
  doc["can_log"] = {
      {"file", "can/session.log"}, {"interface", header.can_interface}, {"node", header.can_node}};
  if (header.can_protocol > 0) doc["can_log"]["protocol"] = header.can_protocol;
  if (header.simulation) doc["simulation"] = *header.simulation;
  if (header.electronics) {
    doc["electronics"] = *header.electronics;
    // The writer records the typed convention (session.hpp): take the declared one over.
    if (const auto it = header.electronics->find("iq_convention");
        it != header.electronics->end() && it->is_string()) {
      if (const auto parsed = estimator::ParseIqConvention(it->get<std::string>()))
        s.iq_convention = *parsed;
    }
  }
  if (header.fixture) doc["fixture"] = *header.fixture;
  json runs = json::array();
  for (const PlannedRun& plan : header.runs) {
    session::RunEntry entry{plan.id, internal::RunFileName(plan.id), plan.commanded_omega_rad_s,
                            kRunPlanned};
    runs.push_back(json{{"id", plan.id}, {"plan", internal::ToJson(plan)}});
    s.runs.push_back(std::move(entry));
  }
  doc["runs"] = std::move(runs);
  s.document = std::move(doc);

  CandumpLogOptions log_options;
  log_options.interface_name = header.can_interface;
  log_options.flush_interval_ns = options.flush_interval_ns;
  auto log = CandumpLogWriter::Open(dir / "can" / "session.log", log_options);
  if (!log) return std::unexpected(log.error());
  impl->can_log = std::move(*log);
  session::KillPoint("record.can_log");
  if (auto written = impl->WriteJson(); !written) return std::unexpected(written.error());
  session::KillPoint("record.json");
  impl->Reserve();
  return SessionRecorder(std::move(impl));
}

std::expected<void, RecordError> SessionRecorder::BeginRun(int run_id, const RunStart& start) {
  Impl& m = *impl_;
  if (m.closed) return std::unexpected(m.WrongState("session is closed"));
  if (m.open_run) {
    return std::unexpected(m.WrongState("run " + std::to_string(*m.open_run) + " is still open"));
  }
  const int index = m.IndexOf(run_id);
  if (index < 0) {
    return std::unexpected(RecordError{RecordErrorKind::kInvalidArgument, m.dir,
                                       "run " + std::to_string(run_id) + " is not planned"});
  }
  const auto i = static_cast<std::size_t>(index);
  session::RunEntry& entry = m.session.runs[i];
  if (entry.status == kRunComplete) {
    return std::unexpected(m.WrongState("run " + std::to_string(run_id) + " is complete"));
  }
  json& object = m.RunObject(i);
  const std::string final_name = internal::RunFileName(run_id);
  // An earlier attempt that ended (aborted, rejected) or failed: keep it aside, never overwrite.
  if (entry.status != kRunPlanned && entry.status != kRunInterrupted) {
    json attempt{{"status", entry.status}};
    if (object.contains("start")) attempt["start"] = object["start"];
    if (object.contains("end")) attempt["end"] = object["end"];
    std::error_code ec;
    const std::size_t k = object.contains("attempts") ? object["attempts"].size() + 1 : 1;
    for (const auto& [from, to] :
         {std::pair{final_name, final_name + ".attempt-" + std::to_string(k)},
          std::pair{final_name + ".partial", final_name + ".interrupted"}}) {
      if (!fs::exists(m.dir / from, ec)) continue;
      auto moved = m.MoveAside(m.dir / from, to);
      if (!moved) return std::unexpected(moved.error());
      attempt["file"] = *moved;
    }
    object["attempts"].push_back(std::move(attempt));
  }

  auto stream = internal::RunCsvStream::Open(
      m.dir / (final_name + ".partial"), start.with_measured_omega, start.with_temperature,
      start.with_resonant_frequency, m.options.flush_interval_ns);
  if (!stream) return std::unexpected(stream.error());
  m.stream = std::move(*stream);
  m.open_run = run_id;
  entry.status = kRunRunning;
  object["start"] = internal::ToJson(start);
  object.erase("end");
  if (auto written = m.WriteJson(); !written) {
    m.stream->Close();
    m.stream.reset();
    m.open_run.reset();
    m.failed_runs.emplace_back(run_id, written.error().ToString());
    return written;
  }
  session::KillPoint("run.begin");
  return {};
}

std::expected<void, RecordError> SessionRecorder::AppendSamples(
    std::span<const GyroSampleRecord> samples) {
  Impl& m = *impl_;
  if (!m.open_run) return std::unexpected(m.WrongState("no run is open"));
  auto appended = m.stream->Append(samples);
  if (!appended && appended.error().kind == RecordErrorKind::kIo) {
    m.failed_runs.emplace_back(*m.open_run, appended.error().ToString());
    m.stream->Close();
    m.stream.reset();
    m.open_run.reset();
  }
  return appended;
}

std::expected<void, RecordError> SessionRecorder::EndRun(const RunEnd& end) {
  Impl& m = *impl_;
  if (!m.open_run) return std::unexpected(m.WrongState("no run is open"));
  const int run_id = *m.open_run;
  auto refuse = [&](std::string message) {
    return std::unexpected(RecordError{RecordErrorKind::kInvalidArgument, m.dir,
                                       "run " + std::to_string(run_id) + ": " + message});
  };
  const bool complete = end.status == kRunComplete;
  if (!complete && end.status != kRunAborted && end.status != kRunRejected) {
    return refuse("end status '" + end.status + "' is not complete, aborted or rejected");
  }
  if (!complete && end.reason.empty()) return refuse("a " + end.status + " run needs a reason");
  if (complete && !std::isfinite(end.omega_rad_s)) return refuse("complete run with non-finite Ω");

  const auto i = static_cast<std::size_t>(m.IndexOf(run_id));
  const std::uint64_t samples = m.stream->samples();
  auto finished = m.stream->Finish(m.dir / internal::RunFileName(run_id));
  m.stream.reset();
  m.open_run.reset();
  if (!finished) {
    m.failed_runs.emplace_back(run_id, finished.error().ToString());
    return finished;
  }
  // The raw frames of a finished run are as durable as its samples.
  std::expected<void, RecordError> log_synced;
  if (m.can_log && m.can_log->is_open()) log_synced = m.can_log->Sync();

  session::RunEntry& entry = m.session.runs[i];
  entry.status = end.status;
  if (std::isfinite(end.omega_rad_s)) entry.omega_rad_s = end.omega_rad_s;
  m.RunObject(i)["end"] = internal::ToJson(end, samples);
  if (auto written = m.WriteJson(); !written) return written;
  session::KillPoint("run.end");
  return log_synced;
}

std::expected<void, RecordError> SessionRecorder::AppendCanFrames(
    std::span<const LoggedCanFrame> frames) {
  Impl& m = *impl_;
  if (m.closed) return std::unexpected(m.WrongState("session is closed"));
  if (!m.can_log) return std::unexpected(m.WrongState("CAN log not open"));
  return m.can_log->Append(frames);
}

std::expected<void, RecordError> SessionRecorder::BeginPrompt(const PromptShown& prompt) {
  Impl& m = *impl_;
  if (m.closed) return std::unexpected(m.WrongState("session is closed"));
  if (m.open_run) return std::unexpected(m.WrongState("a prompt cannot open while a run is open"));
  if (m.open_prompt) return std::unexpected(m.WrongState("another prompt is open"));
  if (prompt.id.empty()) {
    return std::unexpected(
        RecordError{RecordErrorKind::kInvalidArgument, m.dir, "a prompt needs an id"});
  }
  namespace keys = session::keys;
  json entry = json::object();
  entry[keys::kId] = prompt.id;
  entry[keys::kAt] = prompt.at;
  entry[keys::kText] = prompt.text;
  entry[keys::kImageSha256] =
      prompt.image_sha256.empty() ? json(nullptr) : json(prompt.image_sha256);
  entry[keys::kShown] = internal::TimeStampNow();
  json& prompts = m.session.document[keys::kPrompts];
  if (!prompts.is_array()) prompts = json::array();
  prompts.push_back(std::move(entry));
  m.open_prompt = prompts.size() - 1;
  return m.WriteJson();
}

std::expected<void, RecordError> SessionRecorder::EndPrompt(const PromptAnswered& answer) {
  Impl& m = *impl_;
  if (!m.open_prompt) return std::unexpected(m.WrongState("no prompt is open"));
  if (answer.answer != kPromptConfirmed && answer.answer != kPromptAborted &&
      answer.answer != kPromptInterrupted) {
    return std::unexpected(RecordError{RecordErrorKind::kInvalidArgument, m.dir,
                                       "prompt answer '" + answer.answer + "' is not " +
                                           kPromptConfirmed + ", " + kPromptAborted + " or " +
                                           kPromptInterrupted});
  }
  namespace keys = session::keys;
  json& entry = m.session.document[keys::kPrompts][*m.open_prompt];
  entry[keys::kAnswer] = answer.answer;
  entry[keys::kBy] = answer.by.empty() ? json(nullptr) : json(answer.by);
  entry[keys::kHow] = answer.how.empty() ? json(nullptr) : json(answer.how);
  entry[keys::kAnswered] = internal::TimeStampNow();
  m.open_prompt.reset();
  return m.WriteJson();
}

std::expected<void, RecordError> SessionRecorder::Close(const SessionOutcome& outcome) {
  Impl& m = *impl_;
  if (m.closed) return std::unexpected(m.WrongState("session is closed"));
  if (outcome.kind != OutcomeKind::kPass && outcome.reason.empty()) {
    return std::unexpected(
        RecordError{RecordErrorKind::kInvalidArgument, m.dir,
                    std::string(ToString(outcome.kind)) + " outcome needs a reason"});
  }
  m.closed = true;
  std::expected<void, RecordError> first_error;
  auto keep = [&first_error](std::expected<void, RecordError> result) {
    if (!result && first_error) first_error = std::move(result);
  };
  if (m.open_prompt) {
    m.session.document[session::keys::kPrompts][*m.open_prompt][session::keys::kReason] =
        outcome.reason;
    keep(EndPrompt({.answer = kPromptInterrupted, .by = "", .how = ""}));
  }
  if (m.open_run) {
    RunEnd aborted;
    aborted.status = kRunAborted;
    aborted.reason = "session closed: " + outcome.reason;
    keep(EndRun(aborted));  // EndRun does not look at `closed`
  }
  // Runs an I/O failure cut short: say so instead of leaving "running".
  for (const auto& [run_id, reason] : m.failed_runs) {
    const int index = m.IndexOf(run_id);
    if (index < 0 || m.session.runs[static_cast<std::size_t>(index)].status != kRunRunning) {
      continue;
    }
    m.session.runs[static_cast<std::size_t>(index)].status = kRunAborted;
    m.RunObject(static_cast<std::size_t>(index))["end"] =
        json{{"status", kRunAborted}, {"reason", "recorder: " + reason}};
  }
  if (m.can_log && m.can_log->is_open()) keep(m.can_log->Close());
  m.can_log.reset();
  json& doc = m.session.document;
  doc["state"] = "closed";
  doc["ended"] = internal::TimeStampNow();
  doc["outcome"] = internal::ToJson(outcome);
  auto written = m.WriteJson();
  // A full disk: the reserve makes room for the record to say why the session ended.
  if (!written && written.error().kind == RecordErrorKind::kIo && m.ReleaseReserve())
    written = m.WriteJson();
  keep(std::move(written));
  m.ReleaseReserve();  // a closed record needs none
  return first_error;
}

const fs::path& SessionRecorder::directory() const noexcept { return impl_->dir; }

std::vector<RecordedRun> SessionRecorder::Runs() const {
  std::vector<RecordedRun> out;
  for (std::size_t i = 0; i < impl_->session.runs.size(); ++i) {
    const json& object = impl_->session.document["runs"][i];
    const auto attempts = object.find("attempts");
    out.push_back(RecordedRun{
        impl_->plans[i], impl_->session.runs[i].status, impl_->session.runs[i].file,
        attempts != object.end() && attempts->is_array() ? static_cast<int>(attempts->size()) : 0});
  }
  return out;
}

std::vector<int> SessionRecorder::CompleteRunIds() const {
  std::vector<int> out;
  for (const session::RunEntry& run : impl_->session.runs) {
    if (run.status == kRunComplete) out.push_back(run.id);
  }
  return out;
}

std::vector<int> SessionRecorder::RemainingRunIds() const {
  std::vector<int> out;
  for (const session::RunEntry& run : impl_->session.runs) {
    if (run.status != kRunComplete) out.push_back(run.id);
  }
  return out;
}

std::optional<int> SessionRecorder::open_run_id() const noexcept { return impl_->open_run; }

std::uint64_t SessionRecorder::samples_in_open_run() const noexcept {
  return impl_->stream ? impl_->stream->samples() : 0;
}

}  // namespace hrgbench::bench
