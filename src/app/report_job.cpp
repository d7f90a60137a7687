#include "app/report_job.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "app/utc_now.hpp"
#include "hrgbench/session/session.hpp"

extern char** environ;

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kFormat = "hrgbench-report-job";
constexpr int kVersion = 1;
// A job record names a handful of files; anything larger is not one.
constexpr std::uintmax_t kMaxJobFileBytes = 64 * 1024;
constexpr std::size_t kMaxFiles = 256;

// The program a live job's pid runs: its /proc/PID/cmdline's first word's file name. Empty when
// the process is gone (or not ours to read).
std::string ProgramOf(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline", std::ios::binary);
  std::string argv0;
  if (!in || !std::getline(in, argv0, '\0')) return {};
  return fs::path(argv0).filename().string();
}

std::expected<std::string, std::string> StringOrNull(const nlohmann::json& doc,
                                                     const std::string& key,
                                                     const std::string& where) {
  if (!doc.contains(key) || doc.at(key).is_null()) return std::string();
  if (!doc.at(key).is_string()) return std::unexpected(where + key + ": not a string");
  return doc.at(key).get<std::string>();
}

}  // namespace

std::string_view ToString(ReportJobState state) {
  switch (state) {
    case ReportJobState::kRunning:
      return "running";
    case ReportJobState::kWritten:
      return "written";
    case ReportJobState::kFailed:
      return "failed";
    case ReportJobState::kInterrupted:
      return "interrupted";
  }
  return "running";
}

std::optional<ReportMode> ParseReportMode(std::string_view text) {
  if (text == "wait") return ReportMode::kWait;
  if (text == "background") return ReportMode::kBackground;
  if (text == "none") return ReportMode::kNone;
  return std::nullopt;
}

fs::path ReportJobFile(const fs::path& session_dir) { return session_dir / "report" / "job.json"; }

std::expected<void, std::string> WriteReportJob(const fs::path& session_dir, const ReportJob& job) {
  // An interrupted job is what a reader concludes, never what a job writes.
  const ReportJobState state =
      job.state == ReportJobState::kInterrupted ? ReportJobState::kFailed : job.state;
  const auto text_or_null = [](const std::string& text) {
    return text.empty() ? nlohmann::json(nullptr) : nlohmann::json(text);
  };
  const nlohmann::json doc = {{"format", kFormat},
                              {"version", kVersion},
                              {"state", ToString(state)},
                              {"pid", job.pid},
                              {"started", job.started},
                              {"ended", text_or_null(job.ended)},
                              {"reason", text_or_null(job.reason)},
                              {"files", job.files},
                              {"log", text_or_null(job.log)}};
  std::error_code ec;
  fs::create_directories(session_dir / "report", ec);
  if (ec) return std::unexpected((session_dir / "report").string() + ": " + ec.message());
  if (auto written = session::WriteFileAtomic(ReportJobFile(session_dir), doc.dump(1) + "\n");
      !written)
    return std::unexpected(written.error().ToString());
  return {};
}

std::expected<std::optional<ReportJob>, std::string> ReadReportJob(const fs::path& session_dir) {
  const fs::path file = ReportJobFile(session_dir);
  const std::string where = file.string() + ": ";
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::optional<ReportJob>();
  const auto size = fs::file_size(file, ec);
  if (ec) return std::unexpected(where + "cannot read: " + ec.message());
  if (size > kMaxJobFileBytes)
    return std::unexpected(where + std::to_string(size) +
                           " bytes; a report job's record has at most " +
                           std::to_string(kMaxJobFileBytes));
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json doc = nlohmann::json::parse(text.str(), nullptr, false);
  if (!doc.is_object()) return std::unexpected(where + "not a JSON object");
  if (doc.value("format", "") != kFormat)
    return std::unexpected(where + "format: not \"" + std::string(kFormat) + "\"");
  ReportJob job;
  const std::string state = doc.value("state", "");
  if (state == "running")
    job.state = ReportJobState::kRunning;
  else if (state == "written")
    job.state = ReportJobState::kWritten;
  else if (state == "failed")
    job.state = ReportJobState::kFailed;
  else
    return std::unexpected(where + "state: \"" + state.substr(0, 40) +
                           "\" is not running, written or failed");
  if (!doc.contains("pid") || !doc.at("pid").is_number_integer() ||
      doc.at("pid").get<long long>() < 0 || doc.at("pid").get<long long>() > 0x7fffffff)
    return std::unexpected(where + "pid: missing or not a process id");
  job.pid = static_cast<pid_t>(doc.at("pid").get<long long>());
  for (auto [key, field] : {std::pair{"started", &job.started}, std::pair{"ended", &job.ended},
                            std::pair{"reason", &job.reason}, std::pair{"log", &job.log}}) {
    auto value = StringOrNull(doc, key, where);
    if (!value) return std::unexpected(value.error());
    *field = std::move(*value);
  }
  if (doc.contains("files")) {
    const nlohmann::json& files = doc.at("files");
    if (!files.is_array() || files.size() > kMaxFiles)
      return std::unexpected(where + "files: not a list of at most " + std::to_string(kMaxFiles));
    for (const nlohmann::json& f : files) {
      if (!f.is_string()) return std::unexpected(where + "files: not a list of file names");
      job.files.push_back(f.get<std::string>());
    }
  }
  if (job.state == ReportJobState::kRunning && ProgramOf(job.pid) != "hrg-report") {
    job.state = ReportJobState::kInterrupted;
    job.reason = "the report job (pid " + std::to_string(job.pid) +
                 ") ended without finishing the report (killed?)";
  }
  return job;
}

std::expected<pid_t, std::string> StartReportJob(const std::vector<fs::path>& session_dirs,
                                                 const std::string& results_url,
                                                 const fs::path& log) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return std::unexpected("/proc/self/exe: " + ec.message());
  const fs::path program = self.parent_path() / "hrg-report";
  fs::create_directories(log.parent_path(), ec);
  if (ec) return std::unexpected("report job: " + log.parent_path().string() + ": " + ec.message());
  // The job waits for this end of a pipe to close: by then every job.json says "running" with its
  // pid, so the job's own "written" can never be overwritten by its starter's "running".
  int go[2];
  if (::pipe2(go, O_CLOEXEC) != 0)
    return std::unexpected(std::string("report job: pipe: ") + std::strerror(errno));
  std::vector<std::string> args{program.string(), "--job", "--job-start-fd", "3"};
  if (!results_url.empty()) {
    args.push_back("--results");
    args.push_back(results_url);
  }
  for (const fs::path& dir : session_dirs) args.push_back(dir.string());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  posix_spawn_file_actions_adddup2(&actions, go[0], 3);
  // Nothing else: a panel's event pipe held open by the job would keep the panel waiting for it.
  posix_spawn_file_actions_addclosefrom_np(&actions, 4);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none;
  sigemptyset(&none);
  sigset_t defaults;
  sigemptyset(&defaults);
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT}) sigaddset(&defaults, s);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes,
                           POSIX_SPAWN_SETSID | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = 0;
  const int spawned =
      ::posix_spawn(&pid, program.c_str(), &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(go[0]);
  if (spawned != 0) {
    ::close(go[1]);
    return std::unexpected("report job: cannot start " + program.string() + " (its output to " +
                           log.string() + "): " + std::strerror(spawned));
  }
  std::string failed;
  for (const fs::path& dir : session_dirs) {
    ReportJob job;
    job.pid = pid;
    job.started = UtcNowText();
    job.log = log.string();
    if (auto written = WriteReportJob(dir, job); !written && failed.empty())
      failed = written.error();
  }
  ::close(go[1]);  // go
  if (!failed.empty()) return std::unexpected("report job " + std::to_string(pid) + ": " + failed);
  return pid;
}

}  // namespace hrgbench::app
