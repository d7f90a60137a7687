#include "hrgbench/bench/events/session_events.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "hrgbench/analysis/verdict_json.hpp"

namespace hrgbench::bench {
namespace {

// Non-finite numbers are null in every event (JSON has no NaN).
nlohmann::json Number(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json Event(const char* type) {
  nlohmann::json event = nlohmann::json::object();
  event["type"] = type;
  return event;
}

// A prompt's image as a data: URI, so the page needs no second request to a file the panel would
// have to be allowed to serve. The loader bounded its size; read again with the same bound (the
// file may have changed since). null when there is none or it cannot be read.
nlohmann::json ImageDataUri(const std::filesystem::path& file) {
  if (file.empty()) return nullptr;
  std::ifstream in(file, std::ios::binary);
  std::string bytes;
  bytes.resize(static_cast<std::size_t>(kMaxPromptImageBytes) + 1);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  const auto got = static_cast<std::size_t>(in.gcount());
  if (got == 0 || got > kMaxPromptImageBytes) return nullptr;
  bytes.resize(got);
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const char* mime = extension == ".png"   ? "image/png"
                     : extension == ".svg" ? "image/svg+xml"
                                           : "image/jpeg";
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string uri = std::string("data:") + mime + ";base64,";
  uri.reserve(uri.size() + (got + 2) / 3 * 4);
  for (std::size_t i = 0; i < got; i += 3) {
    const auto byte = [&](std::size_t k) {
      return k < got ? static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[k])) : 0u;
    };
    const std::uint32_t triple = byte(i) << 16 | byte(i + 1) << 8 | byte(i + 2);
    uri += kDigits[triple >> 18 & 63];
    uri += kDigits[triple >> 12 & 63];
    uri += i + 1 < got ? kDigits[triple >> 6 & 63] : '=';
    uri += i + 2 < got ? kDigits[triple & 63] : '=';
  }
  return uri;
}

}  // namespace

std::string EventPhaseName(std::string_view sequencer_phase) {
  if (sequencer_phase == "table") return "settle";
  return std::string(sequencer_phase);
}

SessionEventPublisher::SessionEventPublisher(EventStream& stream, SessionEventOptions options)
    : stream_(stream), options_(options) {}

void SessionEventPublisher::SessionStarted(const BenchConfigs& configs,
                                           const std::string& unit_serial,
                                           const std::string& session_dir, bool resume,
                                           const std::string& software_version) {
  nlohmann::json event = Event("session_started");
  event["unit"] = unit_serial;
  event["station"] = configs.station.name;
  event["station_kind"] = std::string(ToString(configs.station.kind));
  event["sequence"] = configs.sequence.name;
  event["limits"] =
      configs.limits.file.empty() ? nlohmann::json(nullptr) : nlohmann::json(configs.limits.name);
  event["session"] = session_dir;
  event["resume"] = resume;
  event["software_version"] = software_version;
  nlohmann::json plan = nlohmann::json::array();
  samples_expected_.clear();
  int id = 1;
  for (const SequenceRun& run : configs.sequence.runs) {
    samples_expected_.push_back(run.Samples());
    plan.push_back({{"run_id", id++},
                    {"omega_rad_s", run.omega_rad_s},
                    {"free_run_s", run.free_run_s},
                    {"sample_rate_hz", run.sample_rate_hz},
                    {"samples", run.Samples()}});
  }
  event["plan"] = std::move(plan);
  stream_.Publish(std::move(event));
}

void SessionEventPublisher::Attach(RunnerOptions& options) {
  auto progress = options.on_progress;
  options.on_progress = [this, progress](const Progress& p) {
    if (progress) progress(p);
    OnProgress(p);
  };
  auto log = options.on_log;
  options.on_log = [this, log](std::string_view line) {
    if (log) log(line);
    nlohmann::json event = Event("log");
    event["message"] = std::string(line);
    stream_.Publish(std::move(event));
  };
  auto samples = options.on_samples;
  options.on_samples = [this, samples](int run_id, std::span<const GyroSampleRecord> records) {
    if (samples) samples(run_id, records);
    OnSamples(run_id, records);
  };
  auto run_end = options.on_run_end;
  options.on_run_end = [this, run_end](int run_id, const RunEnd& end, std::uint64_t n) {
    if (run_end) run_end(run_id, end, n);
    OnRunEnd(run_id, end, n);
  };
  auto prompt = options.on_prompt;
  options.on_prompt = [this, prompt](const PromptRequest& request, const PromptReply* reply) {
    if (prompt) prompt(request, reply);
    nlohmann::json event = Event(reply == nullptr ? "prompt" : "prompt_answered");
    event["id"] = request.id;
    if (reply == nullptr) {
      event["at"] = request.at;
      event["text"] = request.text;
      event["image"] = ImageDataUri(request.image_file);
    } else {
      event["answer"] = reply->confirmed ? "confirm" : "abort";
      event["by"] = reply->by;
      event["how"] = reply->how;
    }
    stream_.Publish(std::move(event));
  };
  auto decided = options.on_decided;
  options.on_decided = [this, decided](std::size_t unit, const EarlyEnd& end) {
    if (decided) decided(unit, end);
    nlohmann::json event = Event("decided");
    event["unit"] = unit;
    if (unit < units_.size()) {
      event["position"] = units_[unit].value("position", "");
      event["serial"] = units_[unit].value("serial", "");
    }
    event["after_run"] = end.after_run;
    event["planned_runs"] = end.planned_runs;
    event["why"] = end.why;
    event["interim_coverage_factor"] = Number(end.interim_coverage_factor);
    // null: decided after run after_run; a number: that far into its free run (its capture stops).
    event["within_run_s"] = Number(end.within_run_s);
    stream_.Publish(std::move(event));
  };
}

void SessionEventPublisher::OnProgress(const Progress& p) {
  const std::string phase = EventPhaseName(p.phase);
  const bool changed = phase != last_phase_ || p.run_id != last_run_id_;
  const auto now = std::chrono::steady_clock::now();
  if (changed) {
    if (last_phase_ == "capture") FlushSamples();  // the run's tail before its "stop"
    nlohmann::json event = Event("phase");
    event["run"] = p.run;
    event["run_count"] = p.run_count;
    event["run_id"] = p.run_id;
    event["omega_rad_s"] = p.omega_rad_s;
    event["phase"] = phase;
    stream_.Publish(std::move(event));
    last_phase_ = phase;
    last_run_id_ = p.run_id;
  } else if (phase != "stopping" &&  // the table coming to rest: every reading (10 Hz at most)
             now - last_progress_ < std::chrono::duration<double>(options_.min_progress_period_s)) {
    return;
  }
  last_progress_ = now;
  FlushSamples();
  nlohmann::json event = Event("progress");
  event["run"] = p.run;
  event["run_count"] = p.run_count;
  event["run_id"] = p.run_id;
  event["omega_rad_s"] = p.omega_rad_s;
  event["phase"] = phase;
  event["samples"] = p.samples;
  event["samples_expected"] = p.samples_expected;
  event["samples_lost"] = p.samples_lost;
  event["elapsed_s"] = Number(p.elapsed_s);
  event["remaining_s"] = Number(p.remaining_s);
  event["table_rate_rad_s"] = Number(p.table_rate_rad_s);
  stream_.Publish(std::move(event));
}

void SessionEventPublisher::OnSamples(int run_id, std::span<const GyroSampleRecord> samples) {
  if (run_id != plot_run_id_) {
    FlushSamples();
    plot_run_id_ = run_id;
    plot_seen_ = 0;
    const std::uint64_t expected =
        run_id >= 1 && static_cast<std::size_t>(run_id) <= samples_expected_.size()
            ? samples_expected_[static_cast<std::size_t>(run_id - 1)]
            : 0;
    const std::uint64_t points = std::max<std::uint64_t>(options_.plot_points_per_run, 1);
    plot_stride_ = std::max<std::uint64_t>(1, (expected + points - 1) / points);
  }
  for (const GyroSampleRecord& s : samples) {
    if (plot_seen_++ % plot_stride_ != 0) continue;
    plot_t_.push_back(s.t_s);
    plot_y_.push_back({Number(s.y[0]), Number(s.y[1]), Number(s.y[2]), Number(s.y[3])});
  }
}

void SessionEventPublisher::FlushSamples() {
  if (plot_t_.empty()) return;
  nlohmann::json event = Event("samples");
  event["run_id"] = plot_run_id_;
  event["stride"] = plot_stride_;
  event["t_s"] = std::move(plot_t_);
  event["y"] = std::move(plot_y_);
  plot_t_ = nlohmann::json::array();
  plot_y_ = nlohmann::json::array();
  stream_.Publish(std::move(event));
}

void SessionEventPublisher::OnRunEnd(int run_id, const RunEnd& end, std::uint64_t samples) {
  FlushSamples();
  if (end.status != kRunComplete || end.reason.rfind("flagged: ", 0) == 0) {
    nlohmann::json warning = Event("warning");
    warning["message"] = "run " + std::to_string(run_id) + " " + end.status + ": " + end.reason;
    stream_.Publish(std::move(warning));
  }
  stream_.Publish(RunResultEvent("run_result", run_id, end, samples));
}

nlohmann::json SessionEventPublisher::RunResultEvent(const char* type, int run_id,
                                                     const RunEnd& end,
                                                     std::uint64_t samples) const {
  nlohmann::json event = Event(type);
  event["run_id"] = run_id;
  event["status"] = end.status;
  event["reason"] = end.reason;
  event["samples"] = samples;
  event["samples_expected"] =
      run_id >= 1 && static_cast<std::size_t>(run_id) <= samples_expected_.size()
          ? nlohmann::json(samples_expected_[static_cast<std::size_t>(run_id - 1)])
          : nlohmann::json(nullptr);
  event["omega_rad_s"] = Number(end.omega_rad_s);
  event["omega_std_error_rad_s"] = Number(end.omega_std_error_rad_s);
  event["omega_source"] = end.omega_source;
  event["sequence_gaps"] = end.sequence_gaps;
  event["kernel_drops"] = end.kernel_drops;
  event["bad_frames"] = end.bad_frames;
  event["temperature_start_c"] = Number(end.temperature_start_c);
  event["temperature_end_c"] = Number(end.temperature_end_c);
  return event;
}

void SessionEventPublisher::SessionFinished(const SessionResult& result) {
  FlushSamples();
  for (const std::string& w : result.warnings) {
    nlohmann::json event = Event("warning");
    event["message"] = w;
    stream_.Publish(std::move(event));
  }
  if (!result.estimate_json.is_null()) {
    nlohmann::json event = Event("estimate");
    event["estimate"] = result.estimate_json;
    stream_.Publish(std::move(event));
  }
  nlohmann::json failed = nlohmann::json::array();
  if (result.verdict) {
    const nlohmann::json verdict = VerdictJson(*result.verdict);
    for (const nlohmann::json& limit : verdict.value("limits", nlohmann::json::array())) {
      nlohmann::json event = limit;
      event["type"] = "limit";
      if (limit.value("status", "") == "FAIL") failed.push_back(limit.value("quantity", ""));
      stream_.Publish(std::move(event));
    }
    for (const nlohmann::json& check : verdict.value("fit_checks", nlohmann::json::array())) {
      nlohmann::json event = check;
      event["type"] = "fit_check";
      stream_.Publish(std::move(event));
    }
  }
  nlohmann::json event = Event("outcome");
  event["outcome"] = std::string(ToString(result.outcome));
  event["reason"] = result.reason;
  event["exit_code"] = result.exit_code;
  event["complete_runs"] = result.complete_runs;
  event["failed_limits"] = std::move(failed);
  event["session"] = result.dir.string();
  stream_.Publish(std::move(event));
}

void SessionEventPublisher::ReportWritten(const std::string& report_path) {
  nlohmann::json event = Event("report");
  event["path"] = report_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(report_path);
  stream_.Publish(std::move(event));
}

void SessionEventPublisher::ReportBeingWritten(const std::string& report_path, long pid) {
  nlohmann::json event = Event("report");
  event["path"] = report_path;
  event["job"] = {{"state", "running"}, {"pid", pid}};
  stream_.Publish(std::move(event));
}

void SessionEventPublisher::FixtureStarted(nlohmann::json units) {
  units_ = units;
  nlohmann::json event = Event("fixture_started");
  event["units"] = std::move(units);
  stream_.Publish(std::move(event));
}

void SessionEventPublisher::AttachFixture(RunnerOptions& options, nlohmann::json units) {
  units_ = std::move(units);
  Attach(options);
  options.on_samples = nullptr;  // one unit's plot only; a fixture's page shows its units' states
  options.on_run_end = nullptr;
  auto unit_run_end = options.on_unit_run_end;
  options.on_unit_run_end = [this, unit_run_end](std::size_t unit, int run_id, const RunEnd& end,
                                                 std::uint64_t n) {
    if (unit_run_end) unit_run_end(unit, run_id, end, n);
    nlohmann::json event = RunResultEvent("unit_run_result", run_id, end, n);
    event["unit"] = unit;
    if (unit < units_.size()) {
      event["position"] = units_[unit].value("position", "");
      event["serial"] = units_[unit].value("serial", "");
    }
    stream_.Publish(std::move(event));
  };
}

void SessionEventPublisher::UnitFinished(std::size_t unit, const SessionResult& result,
                                         const std::string& report) {
  nlohmann::json failed = nlohmann::json::array();
  if (result.verdict) {
    const nlohmann::json verdict = VerdictJson(*result.verdict);
    for (const nlohmann::json& limit : verdict.value("limits", nlohmann::json::array()))
      if (limit.value("status", "") == "FAIL") failed.push_back(limit.value("quantity", ""));
  }
  nlohmann::json event = Event("unit_outcome");
  event["unit"] = unit;
  if (unit < units_.size()) {
    event["position"] = units_[unit].value("position", "");
    event["serial"] = units_[unit].value("serial", "");
  }
  event["outcome"] = std::string(ToString(result.outcome));
  event["reason"] = result.reason;
  event["exit_code"] = result.exit_code;
  event["complete_runs"] = result.complete_runs;
  event["failed_limits"] = std::move(failed);
  event["session"] = result.dir.string();
  event["report"] = report.empty() ? nlohmann::json(nullptr) : nlohmann::json(report);
  stream_.Publish(std::move(event));
}

void SessionEventPublisher::FixtureFinished(OutcomeKind outcome, int exit_code,
                                            const std::string& reason,
                                            const std::string& fixture_dir) {
  nlohmann::json event = Event("outcome");
  event["outcome"] = std::string(ToString(outcome));
  event["reason"] = reason;
  event["exit_code"] = exit_code;
  event["failed_limits"] = nlohmann::json::array();
  event["session"] = fixture_dir;
  stream_.Publish(std::move(event));
}

}  // namespace hrgbench::bench
