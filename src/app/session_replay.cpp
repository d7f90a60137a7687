#include "app/session_replay.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <system_error>
#include <utility>

#include "gyro_can/gyro_traffic_replay.hpp"
#include "hrgbench/analysis/estimate_method.hpp"
#include "hrgbench/analysis/recorded_estimate.hpp"
#include "hrgbench/bench/capture/capture.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/config/sequence_config.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/session/candump_log.hpp"
#include "hrgbench/session/number_text.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A capture the record began, in the order it began them.
struct BegunCapture {
  int run_id = 0;
  std::string attempt;
  std::string status;
  std::string file;
  std::string utc;
  std::size_t samples_planned = 0;
};

std::size_t PlannedSamples(const session::RunRecord& run) {
  if (!run.plan) return 0;
  const double free_run_s = run.plan->free_run_s;
  const double rate_hz = run.plan->sample_rate_hz;
  // A damaged record's plan keeps nothing rather than an absurd bound.
  if (!(free_run_s > 0.0 && rate_hz >= 1.0 && rate_hz <= hw::kMaxSampleRateCanFdHz &&
        free_run_s * rate_hz <= bench::kMaxSamplesPerRun)) {
    return 0;
  }
  bench::SequenceRun planned;
  planned.free_run_s = free_run_s;
  planned.sample_rate_hz = static_cast<std::uint32_t>(rate_hz);
  return planned.Samples();
}

// A path the record names, if it stays inside the session (relative, no "..").
bool InsideSession(const std::string& name) {
  const fs::path relative(name);
  return !name.empty() && relative.is_relative() &&
         std::none_of(relative.begin(), relative.end(),
                      [](const fs::path& part) { return part == ".."; });
}

std::vector<BegunCapture> BegunCaptures(const session::SessionRecord& record) {
  std::vector<BegunCapture> begun;
  for (const session::RunRecord& run : record.runs) {
    const std::size_t planned = PlannedSamples(run);
    const auto add = [&](const std::optional<session::RunStartRecord>& start,
                         const std::string& status, const std::string& file, std::string attempt) {
      if (!start || start->at.utc.empty()) return;
      begun.push_back({run.id, std::move(attempt), status, file, start->at.utc, planned});
    };
    std::size_t k = 0;
    for (const session::AttemptRecord& attempt : run.attempts) {
      ++k;
      add(attempt.start, attempt.status, attempt.file, "attempt " + std::to_string(k));
    }
    add(run.start, run.status, run.file, "");
  }
  // ISO 8601 UTC with fixed width sorts as text.
  std::stable_sort(begun.begin(), begun.end(),
                   [](const BegunCapture& a, const BegunCapture& b) { return a.utc < b.utc; });
  return begun;
}

// What the bench's capture keeps of what the driver delivered (bench/capture.hpp: the count stop
// from seq 0, and no sample that is not after the previous one).
// At most `limit` of them (a fingerprint needs only the first few).
std::vector<bench::GyroSampleRecord> KeptSamples(const drivers::gyro_can::ReplayedRun& run,
                                                 std::size_t planned,
                                                 std::size_t limit = SIZE_MAX) {
  std::vector<bench::GyroSampleRecord> kept;
  kept.reserve(std::min({planned, run.samples.size(), limit}));
  bool any = false;
  std::uint32_t last = 0;
  for (const hw::GyroSample& sample : run.samples) {
    if (kept.size() == limit) break;
    if (sample.seq >= planned) continue;
    if (any && sample.seq <= last) continue;
    kept.push_back(bench::ToSampleRecord(sample, run.release_t_ns));
    any = true;
    last = sample.seq;
  }
  return kept;
}

bool SameBits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

std::string Values(double recorded, double rebuilt) {
  return "recorded " + session::NumberText(recorded) + ", rebuilt " + session::NumberText(rebuilt);
}

// The first difference between a recorded run file and the rebuilt samples, "" when none in the
// first `compare` samples.
std::string FirstDifference(const session::RunSamples& recorded,
                            const std::vector<bench::GyroSampleRecord>& rebuilt,
                            std::size_t compare) {
  const auto seq = recorded.extra_columns.find("seq");
  static constexpr const char* kY[] = {"y1", "y2", "y3", "y4"};
  for (std::size_t k = 0; k < compare; ++k) {
    // Named only when the sample differs: the loop runs over every sample of a session.
    const auto where = [&] {
      return "sample " + std::to_string(k + 1) + " (line " + std::to_string(k + 2) + ", seq " +
             std::to_string(rebuilt[k].seq) + "): ";
    };
    if (seq != recorded.extra_columns.end() &&
        !SameBits(seq->second[k], static_cast<double>(rebuilt[k].seq))) {
      return where() + "seq " + Values(seq->second[k], rebuilt[k].seq);
    }
    if (!SameBits(recorded.t_s[k], rebuilt[k].t_s))
      return where() + "t_s " + Values(recorded.t_s[k], rebuilt[k].t_s);
    for (int c = 0; c < 4; ++c) {
      if (!SameBits(recorded.y(c, static_cast<Eigen::Index>(k)), rebuilt[k].y[c]))
        return where() + kY[c] + " " +
               Values(recorded.y(c, static_cast<Eigen::Index>(k)), rebuilt[k].y[c]);
    }
  }
  return "";
}

// The recorded file of a capture: as named, else its .partial (a run the bench stopped).
fs::path RecordedFile(const fs::path& dir, const std::string& file) {
  if (!InsideSession(file)) return {};
  std::error_code ec;
  if (!file.empty() && fs::exists(dir / file, ec)) return dir / file;
  if (!file.empty() && fs::exists(dir / (file + ".partial"), ec)) return dir / (file + ".partial");
  return {};
}

// A recorded capture's file, read (or why not).
struct RecordedCapture {
  fs::path file;  // empty: not in the session
  std::expected<session::RunSamples, session::SessionError> samples =
      std::unexpected(session::SessionError{});
};

RecordedCapture ReadRecorded(const fs::path& dir, const BegunCapture& begun) {
  RecordedCapture recorded;
  recorded.file = RecordedFile(dir, begun.file);
  if (!recorded.file.empty()) recorded.samples = session::ReadRunCsv(recorded.file, 0);
  return recorded;
}

// The rebuilt samples start as the recorded ones do: the capture they belong to. Noise makes a
// few samples a fingerprint.
constexpr std::size_t kFingerprintSamples = 8;

bool StartsAlike(const RecordedCapture& recorded,
                 const std::vector<bench::GyroSampleRecord>& rebuilt) {
  if (!recorded.samples || recorded.samples->size() == 0 || rebuilt.empty()) return false;
  const std::size_t n = std::min({recorded.samples->size(), rebuilt.size(), kFingerprintSamples});
  return FirstDifference(*recorded.samples, rebuilt, n).empty();
}

void Compare(const fs::path& dir, const BegunCapture& begun, const RecordedCapture& recorded,
             const std::vector<bench::GyroSampleRecord>& rebuilt, ReplayedCapture& capture) {
  capture.rebuilt_samples = rebuilt.size();
  if (recorded.file.empty()) {
    capture.difference = "the recorded file '" + begun.file + "' is not in the session folder";
    return;
  }
  capture.file = fs::relative(recorded.file, dir).string();
  const bool complete = begun.status == bench::kRunComplete;
  if (!recorded.samples) {
    if (complete) {
      capture.difference =
          "the recorded file cannot be read: " + recorded.samples.error().ToString();
    } else {
      capture.compared = false;
      capture.note = "not compared: the recorded file was cut by the stop (" +
                     recorded.samples.error().ToString() + ")";
    }
    return;
  }
  const session::RunSamples& samples = *recorded.samples;
  capture.recorded_samples = samples.size();
  const std::size_t common = std::min(samples.size(), rebuilt.size());
  capture.difference = FirstDifference(samples, rebuilt, common);
  if (!capture.difference.empty()) return;
  if (samples.size() == rebuilt.size()) {
    capture.identical = true;
  } else if (!complete && samples.size() < rebuilt.size()) {
    // A run cut short keeps what reached the disk before the stop: the rebuilt run's beginning.
    capture.identical = true;
    capture.note = "the record kept the first " + std::to_string(samples.size()) + " of " +
                   std::to_string(rebuilt.size()) + " samples (the run was " + begun.status + ")";
  } else if (!complete) {
    // The run file and the log are written out independently (each at most every 200 ms): after
    // a kill -9 either may hold more of the run than the other.
    capture.identical = true;
    capture.note = "the log kept the first " + std::to_string(rebuilt.size()) + " of the " +
                   std::to_string(samples.size()) + " recorded samples (the run was " +
                   begun.status + "; a crash loses the log's unwritten tail)";
  } else {
    capture.difference = "recorded " + std::to_string(samples.size()) + " samples, rebuilt " +
                         std::to_string(rebuilt.size());
  }
}

// A string member of a JSON Patch operation (RFC 6902: "op", "path"), "" when absent.
std::string StringAt(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || !object.at(key).is_string()) return "";
  return object.at(key).get<std::string>();
}

std::string FirstJsonDifference(const json& recorded, const json& rebuilt) {
  const json patch = json::diff(recorded, rebuilt);
  if (patch.empty()) return "";
  const json& op = patch.front();
  const std::string path = StringAt(op, "path");
  std::string text = StringAt(op, "op") + " at " + path;
  try {
    const json::json_pointer pointer(path);
    if (recorded.contains(pointer)) text += ": recorded " + recorded.at(pointer).dump();
    if (rebuilt.contains(pointer)) text += ", rebuilt " + rebuilt.at(pointer).dump();
  } catch (const json::exception&) {
    // A path the diff made is always valid; nothing to add if not.
  }
  return text + " (" + std::to_string(patch.size()) + " differences)";
}

void CompareEstimate(
    const fs::path& dir, const session::SessionRecord& record,
    const estimator::FitQualityLimits& fit,
    const std::vector<std::pair<int, const std::vector<bench::GyroSampleRecord>*>>& final_captures,
    SessionReplay& replay) {
  if (!record.outcome || !record.outcome->estimate) {
    replay.estimate_difference = "not compared: the record holds no estimate";
    return;
  }
  session::ReadOptions read;
  read.min_samples_per_run = bench::MinimumSamples(bench::Method::kMl);
  auto recorded = session::ReadSession(dir, read);
  if (!recorded) {
    replay.estimate_difference = "not compared: " + recorded.error().ToString();
    return;
  }
  for (std::size_t i = 0; i < recorded->loaded_run_ids.size(); ++i) {
    const int id = recorded->loaded_run_ids[i];
    const auto found = std::find_if(final_captures.begin(), final_captures.end(),
                                    [id](const auto& c) { return c.first == id; });
    if (found == final_captures.end()) {
      replay.estimate_difference =
          "not compared: run " + std::to_string(id) + " was not rebuilt from the log";
      return;
    }
    const std::vector<bench::GyroSampleRecord>& rebuilt = *found->second;
    session::RunSamples& samples = recorded->loaded_samples[i];
    if (rebuilt.size() != samples.size()) {
      replay.estimate_difference = "not compared: run " + std::to_string(id) + " rebuilt " +
                                   std::to_string(rebuilt.size()) + " samples, recorded " +
                                   std::to_string(samples.size());
      return;
    }
    // The rebuilt samples replace the recorded ones; the table's columns stay (not in the log).
    for (std::size_t k = 0; k < rebuilt.size(); ++k) {
      samples.t_s[k] = rebuilt[k].t_s;
      for (int c = 0; c < 4; ++c) samples.y(c, static_cast<Eigen::Index>(k)) = rebuilt[k].y[c];
    }
  }
  const bench::RecordedEstimate estimate =
      bench::EstimateRecordedSession(std::move(*recorded), record, fit);
  replay.estimate_compared = true;
  replay.estimate_difference = FirstJsonDifference(record.outcome->estimate_json, estimate.report);
  replay.estimate_identical = replay.estimate_difference.empty();
}

std::expected<void, std::string> StartRebuiltSession(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  if (fs::exists(to, ec) && !fs::is_empty(to, ec))
    return std::unexpected(to.string() + ": exists and is not empty");
  if (auto made = session::CreateDirectoriesDurably(to / "runs"); !made)
    return std::unexpected(made.error().ToString());
  for (const char* part : {"config", "can"}) {
    fs::copy(from / part, to / part, fs::copy_options::recursive, ec);
    if (ec) return std::unexpected((to / part).string() + ": " + ec.message());
  }
  fs::copy_file(from / "session.json", to / "session.json", ec);
  if (ec) return std::unexpected((to / "session.json").string() + ": " + ec.message());
  return {};
}

// A complete run's file from its rebuilt samples: y and seq, the electronics' conditions (temp_c,
// freq_hz) when the log's status reports stamp every sample (as the bench records them), and the
// recorded file's other columns (the table's) when they belong to the same samples.
std::expected<void, std::string> WriteRebuiltRun(
    const fs::path& path, const std::vector<bench::GyroSampleRecord>& rebuilt,
    const RecordedCapture& recorded) {
  session::RunSamples samples;
  samples.y.resize(4, static_cast<Eigen::Index>(rebuilt.size()));
  std::vector<double> seq, temperature_c, frequency_hz;
  seq.reserve(rebuilt.size());
  temperature_c.reserve(rebuilt.size());
  frequency_hz.reserve(rebuilt.size());
  samples.t_s.reserve(rebuilt.size());
  bool conditions = !rebuilt.empty();
  for (std::size_t k = 0; k < rebuilt.size(); ++k) {
    samples.t_s.push_back(rebuilt[k].t_s);
    for (int c = 0; c < 4; ++c) samples.y(c, static_cast<Eigen::Index>(k)) = rebuilt[k].y[c];
    seq.push_back(rebuilt[k].seq);
    temperature_c.push_back(rebuilt[k].temperature_c);
    frequency_hz.push_back(rebuilt[k].resonant_frequency_hz);
    conditions =
        conditions && std::isfinite(temperature_c.back()) && std::isfinite(frequency_hz.back());
  }
  samples.extra_columns.emplace("seq", std::move(seq));
  if (conditions) {
    samples.extra_columns.emplace("temp_c", std::move(temperature_c));
    samples.extra_columns.emplace("freq_hz", std::move(frequency_hz));
  }
  if (recorded.samples && recorded.samples->size() == rebuilt.size() &&
      FirstDifference(*recorded.samples, rebuilt, rebuilt.size()).empty()) {
    for (const auto& [name, values] : recorded.samples->extra_columns)
      samples.extra_columns.emplace(name, values);
  }
  if (auto written = session::WriteRunCsv(path, samples); !written)
    return std::unexpected(written.error().ToString());
  return {};
}

}  // namespace

bool SessionReplay::Identical() const {
  if (log_damage || divergence || !problems.empty()) return false;
  if (estimate_compared && !estimate_identical) return false;
  return std::all_of(captures.begin(), captures.end(),
                     [](const ReplayedCapture& c) { return c.identical || !c.compared; });
}

std::expected<SessionReplay, std::string> ReplaySession(const fs::path& dir,
                                                        const ReplayOptions& options) {
  const auto read = session::ReadSessionRecord(dir);
  if (!read) return std::unexpected(read.error().ToString());
  const session::SessionRecord& record = *read;

  SessionReplay replay;
  if (!options.rebuild_into.empty()) {
    if (auto started = StartRebuiltSession(dir, options.rebuild_into); !started)
      return std::unexpected(started.error());
  }
  std::string log_name = "can/session.log";
  drivers::gyro_can::GyroReplayOptions driver;
  const std::string where = (dir / "session.json").string() + ": field 'can_log.";
  if (record.can_log) {
    const session::CanLogRecord& can_log = *record.can_log;
    log_name = can_log.file;
    if (!InsideSession(log_name)) {
      return std::unexpected(where + "file': '" + log_name + "' is not a file inside the session");
    }
    // The protocol the log speaks: only version 2's identifiers are this driver's. A log without
    // it was recorded before version 2 (version 1's fixed identifiers).
    const auto protocol = can_log.protocol;
    if (protocol != drivers::gyro_can::kProtocolVersion) {
      return std::unexpected(
          where + "protocol': " + (protocol ? std::to_string(*protocol) : "absent (version 1)") +
          ": the log speaks gyro CAN protocol " +
          (protocol ? "v" + std::to_string(*protocol) : "v1") + " and this hrg-bench replays v" +
          std::to_string(drivers::gyro_can::kProtocolVersion) + " only");
    }
    const auto node = can_log.node;
    if (!node || *node < 0 || *node > drivers::gyro_can::kMaxNodeId) {
      return std::unexpected(where + "node': " + (node ? std::to_string(*node) : "absent") +
                             ": a node id 0.." + std::to_string(drivers::gyro_can::kMaxNodeId) +
                             " is needed");
    }
    driver.node = static_cast<drivers::gyro_can::NodeId>(*node);
  }
  replay.log_file = dir / log_name;

  auto configs = bench::LoadSavedConfigs(dir);
  if (configs) {
    driver.ack_timeout_ns = configs->station.gyro.ack_timeout_ms * 1'000'000;
    driver.command_attempts = static_cast<int>(configs->station.gyro.command_attempts);
  } else {
    replay.problems.push_back(
        "the session's saved configs: " + configs.error() +
        " (the driver waits with its defaults; the estimate is not compared)");
  }

  auto reader = bench::CandumpLogReader::Open(replay.log_file);
  if (!reader) return std::unexpected(reader.error().ToString());
  const auto started = std::chrono::steady_clock::now();
  drivers::gyro_can::GyroReplay replayed = drivers::gyro_can::ReplayGyroTraffic(
      [&reader]() -> std::optional<drivers::can_virtual::PlaybackFrame> {
        std::optional<bench::LoggedCanFrame> logged = reader->Next();
        if (!logged) return std::nullopt;
        return drivers::can_virtual::PlaybackFrame{logged->unix_time_ns, logged->frame,
                                                   reader->lines_read()};
      },
      driver);
  replay.replay_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  replay.log_lines = reader->lines_read();
  replay.log_frames = reader->frames_read();
  replay.log_error_frames = reader->error_frames();
  if (reader->damage())
    replay.log_damage = replay.log_file.string() + ": " + reader->damage()->message;
  replay.commands = replayed.commands;
  replay.host_starts = replayed.host_starts;
  replay.acks_taken_late = replayed.acks_taken_late;
  replay.driver_notes = std::move(replayed.notes);
  replay.divergence = std::move(replayed.divergence);

  // Captures to releases, both in order. First each capture with data takes the first release
  // after the previous match whose samples start as its file does; then a capture without a match
  // takes the first free release between its neighbours' (a difference is then reported, not
  // hidden). A release left over was never recorded (the host stopped in between); a capture left
  // over has no release in the log (a kill -9 loses the log's unwritten tail: at most its flush
  // interval).
  const std::vector<BegunCapture> begun = BegunCaptures(record);
  const std::size_t none = replayed.runs.size();
  std::vector<RecordedCapture> recorded(begun.size());
  std::vector<std::size_t> match(begun.size(), none);
  std::vector<bool> taken(replayed.runs.size(), false);
  std::size_t after = 0;
  for (std::size_t k = 0; k < begun.size(); ++k) {
    recorded[k] = ReadRecorded(dir, begun[k]);
    for (std::size_t j = after; j < replayed.runs.size(); ++j) {
      if (StartsAlike(recorded[k], KeptSamples(replayed.runs[j], begun[k].samples_planned,
                                               kFingerprintSamples))) {
        match[k] = j;
        taken[j] = true;
        after = j + 1;
        break;
      }
    }
  }
  for (std::size_t k = 0; k < begun.size(); ++k) {
    if (match[k] != none) continue;
    std::size_t lo = 0;
    for (std::size_t i = k; i-- > 0;) {
      if (match[i] != none) {
        lo = match[i] + 1;
        break;
      }
    }
    std::size_t hi = none;
    for (std::size_t i = k + 1; i < begun.size(); ++i) {
      if (match[i] != none) {
        hi = match[i];
        break;
      }
    }
    for (std::size_t j = lo; j < hi; ++j) {
      if (!taken[j]) {
        match[k] = j;
        taken[j] = true;
        break;
      }
    }
  }

  std::vector<std::vector<bench::GyroSampleRecord>> kept(begun.size());
  std::vector<std::pair<int, const std::vector<bench::GyroSampleRecord>*>> final_captures;
  for (std::size_t k = 0; k < begun.size(); ++k) {
    ReplayedCapture capture;
    capture.run_id = begun[k].run_id;
    capture.attempt = begun[k].attempt;
    capture.status = begun[k].status;
    capture.file = begun[k].file;
    if (match[k] != none) {
      const drivers::gyro_can::ReplayedRun& run = replayed.runs[match[k]];
      capture.release_line = run.release_line;
      kept[k] = KeptSamples(run, begun[k].samples_planned);
      replay.samples_rebuilt += kept[k].size();
      Compare(dir, begun[k], recorded[k], kept[k], capture);
      if (begun[k].attempt.empty()) final_captures.emplace_back(begun[k].run_id, &kept[k]);
    } else if (begun[k].status != bench::kRunComplete) {
      capture.compared = false;
      capture.note =
          "not compared: its release is not in the log (a crash loses the log's "
          "unwritten tail)";
    } else {
      capture.difference = "its release is not in the log";
    }
    replay.captures.push_back(std::move(capture));
  }
  if (!options.rebuild_into.empty()) {
    for (std::size_t k = 0; k < begun.size(); ++k) {
      if (match[k] == none || !begun[k].attempt.empty() || begun[k].status != bench::kRunComplete ||
          !InsideSession(begun[k].file)) {
        continue;
      }
      auto written = WriteRebuiltRun(options.rebuild_into / begun[k].file, kept[k], recorded[k]);
      if (!written) return std::unexpected(written.error());
      replay.rebuilt_files.push_back(begun[k].file);
    }
  }
  for (std::size_t j = 0; j < replayed.runs.size(); ++j) {
    if (taken[j]) continue;
    replay.unrecorded_releases.push_back(
        "line " + std::to_string(replayed.runs[j].release_line) +
        ": a release the record holds no capture of (the host stopped before recording it)");
  }

  if (options.estimate && configs) {
    CompareEstimate(dir, record, configs->limits.fit, final_captures, replay);
  } else if (options.estimate) {
    replay.estimate_difference = "not compared: the session's saved configs cannot be read";
  } else {
    replay.estimate_difference = "not compared (--no-estimate)";
  }
  return replay;
}

json ReplayJson(const SessionReplay& replay) {
  json captures = json::array();
  for (const ReplayedCapture& c : replay.captures) {
    captures.push_back({{"run", c.run_id},
                        {"attempt", c.attempt},
                        {"status", c.status},
                        {"file", c.file},
                        {"release_line", c.release_line},
                        {"recorded_samples", c.recorded_samples},
                        {"rebuilt_samples", c.rebuilt_samples},
                        {"compared", c.compared},
                        {"identical", c.identical},
                        {"difference", c.difference},
                        {"note", c.note}});
  }
  const auto optional_text = [](const std::optional<std::string>& text) {
    return text ? json(*text) : json(nullptr);
  };
  return {{"identical", replay.Identical()},
          {"log",
           {{"file", replay.log_file.string()},
            {"lines", replay.log_lines},
            {"frames", replay.log_frames},
            {"error_frames", replay.log_error_frames},
            {"damage", optional_text(replay.log_damage)}}},
          {"driver",
           {{"commands", replay.commands},
            {"host_starts", replay.host_starts},
            {"acks_taken_late", replay.acks_taken_late},
            {"notes", replay.driver_notes},
            {"divergence", optional_text(replay.divergence)}}},
          {"captures", captures},
          {"problems", replay.problems},
          {"unrecorded_releases", replay.unrecorded_releases},
          {"samples_rebuilt", replay.samples_rebuilt},
          {"rebuilt_files", replay.rebuilt_files},
          {"replay_seconds", replay.replay_seconds},
          {"estimate",
           {{"compared", replay.estimate_compared},
            {"identical", replay.estimate_identical},
            {"difference", replay.estimate_difference}}}};
}

std::string ReplayText(const SessionReplay& replay) {
  std::string out = "log " + replay.log_file.string() + ": " + std::to_string(replay.log_frames) +
                    " frames, " + std::to_string(replay.commands) + " commands replayed";
  if (replay.host_starts > 1)
    out += " (" + std::to_string(replay.host_starts) + " host processes: the session was resumed)";
  out += "\n";
  for (const ReplayedCapture& c : replay.captures) {
    out += "  run " + std::to_string(c.run_id) + (c.attempt.empty() ? "" : " " + c.attempt) + " [" +
           c.status + "]: ";
    if (!c.compared) {
      out += c.note;
    } else if (c.identical) {
      out += std::to_string(c.rebuilt_samples) + " samples rebuilt, identical to " + c.file;
      if (!c.note.empty()) out += "; " + c.note;
    } else {
      out += "DIFFERS: " + c.difference;
    }
    out += "\n";
  }
  if (replay.estimate_compared) {
    out += std::string("  estimate: ") +
           (replay.estimate_identical ? "identical to the recorded one"
                                      : "DIFFERS: " + replay.estimate_difference) +
           "\n";
  } else {
    out += "  estimate: " + replay.estimate_difference + "\n";
  }
  for (const std::string& note : replay.driver_notes)
    out += "  in the recorded traffic the driver met: " + note + "\n";
  for (const std::string& release : replay.unrecorded_releases) out += "  note: " + release + "\n";
  for (const std::string& problem : replay.problems) out += "  problem: " + problem + "\n";
  if (replay.log_damage) out += "  the log is damaged: " + *replay.log_damage + "\n";
  if (replay.divergence) out += "  the driver diverged: " + *replay.divergence + "\n";
  for (const std::string& file : replay.rebuilt_files) out += "  rebuilt: " + file + "\n";
  out += replay.Identical() ? "the raw CAN log rebuilds the record bit for bit\n"
                            : "the raw CAN log does NOT rebuild the record\n";
  return out;
}

}  // namespace hrgbench::app
