#pragma once
// hrg-bench replay: a session's raw CAN log (can/session.log) played back through the gyro
// driver's receive path (drivers/gyro_can/gyro_traffic_replay.hpp over the in-process playback
// bus), every run's samples rebuilt and compared with the recorded run files bit for bit, then the
// estimate made again from the rebuilt samples and compared with the one session.json holds.
//
// What it proves: the raw log is a complete record (the samples, hence the verdict, follow from
// its bytes alone), and a driver change can be checked against recorded traffic (the driver must
// send what the host sent and decode what it decoded).
//
// Matching: the record's captures in the order it began them (runs[].attempts[] and runs[], by
// start.utc), attempts that were run again and runs cut short by a crash included, each to the
// log's next acknowledged release whose samples start as its file does (else simply the next):
// a release the host made but never recorded (killed in between) is skipped and noted. A capture's
// samples are those the bench's capture keeps: seq 0 … round(free_run_s·fs) − 1, increasing.
// Columns from the table (measured Ω, temperature) are not in the CAN log and are not compared.

#include <cstdint>
#include <expected>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace hrgbench::app {

struct ReplayOptions {
  bool estimate = true;  // also make the estimate again and compare it
  // Not empty: a new session folder (refused if it exists and is not empty) that takes the
  // session's record (session.json, config/, can/) and, for every complete run, the run file the
  // log rebuilds: t_s, y1…y4 and seq from the log, the table's columns from the recorded file
  // when it is readable and has the same samples. A run file lost or damaged is restored so; the
  // new folder replays identical and estimates as the record did.
  std::filesystem::path rebuild_into;
};

struct ReplayedCapture {
  int run_id = 0;
  std::string attempt;  // "" for the run's last capture, "attempt 1", ... for earlier ones
  std::string status;   // the record's: "complete", "aborted", "interrupted", ...
  std::string file;     // the recorded run file, relative to the session
  std::uint64_t release_line = 0;  // the Release command's line in the log (0: not in the log)
  std::size_t recorded_samples = 0;
  std::size_t rebuilt_samples = 0;
  // False for a capture cut short whose recorded file was torn by the stop (nothing to hold the
  // rebuilt samples against); `note` says so.
  bool compared = true;
  bool identical = false;
  std::string difference;  // the first difference; empty when identical
  std::string note;        // e.g. "the record kept the first 1200 of 1450 samples (...)"
};

struct SessionReplay {
  std::filesystem::path log_file;
  std::uint64_t log_lines = 0;
  std::uint64_t log_frames = 0;
  std::uint64_t log_error_frames = 0;
  std::optional<std::string> log_damage;  // "…/can/session.log: line 1234: …": read up to there
  std::uint64_t commands = 0;
  int host_starts = 0;
  std::uint64_t acks_taken_late = 0;      // stamped after the host's wait, taken without a resend
  std::vector<std::string> driver_notes;  // what failed again as it failed then
  std::optional<std::string> divergence;  // the driver sent what the host did not
  std::vector<ReplayedCapture> captures;
  std::vector<std::string> problems;  // the saved configs cannot be read
  // Releases in the log the record began no capture of (the host stopped in between): noted, not
  // a difference.
  std::vector<std::string> unrecorded_releases;
  std::uint64_t samples_rebuilt = 0;  // kept by the capture rule, over all captures
  double replay_seconds = 0.0;        // wall time of reading and replaying the log
  // The estimate: compared when the record holds one and every complete run was rebuilt.
  bool estimate_compared = false;
  bool estimate_identical = false;
  std::string estimate_difference;
  std::vector<std::string> rebuilt_files;  // written under rebuild_into, relative to it

  // Every capture identical, the estimate (when compared) identical, nothing damaged or diverged.
  bool Identical() const;
};

// Errors (returned): `dir` is not a readable session, or its CAN log is missing. Everything about
// the log's content is in the result.
std::expected<SessionReplay, std::string> ReplaySession(const std::filesystem::path& dir,
                                                        const ReplayOptions& options = {});

nlohmann::json ReplayJson(const SessionReplay& replay);
// A few lines for a person: one per capture, then the estimate and the verdict on the log.
std::string ReplayText(const SessionReplay& replay);

}  // namespace hrgbench::app
