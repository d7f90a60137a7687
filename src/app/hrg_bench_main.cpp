// hrg-bench: the program a production line runs for every gyro, and CI runs on simulated hardware.
//
//   hrg-bench run --station S.toml --sequence Q.toml [--limits L.toml] --serial SN [-o DIR]
//                 [--operator ID] [--prompts terminal|confirm|fd:N] [--json] [--events FILE|-]
//   hrg-bench run ... --serial SN1 --serial SN2 ...   a fixture: one serial per fitted position
//                 (or POSITION=SN); exit code the worst unit's
//   hrg-bench resume DIR [--operator ID] [--prompts ...] [--json] [--events FILE|-]
//   hrg-bench check S.toml Q.toml [L.toml]
//   hrg-bench replay DIR [--unit POSITION|SERIAL] [--json] [--no-estimate] [--rebuild-into NEW_DIR]
//   hrg-bench serve --station S.toml [--listen 127.0.0.1:8080] [--sessions DIR] [--token-file F]
//
// Exit codes: the table of every program (bench/exit_codes.hpp): 0 PASS, 1 FAIL (a parameter out
// of its limits), 2 ERROR (the bench: timeout, bus-off, Modbus failure, too many drops, disk),
// 3 ABORTED (operator), 4 bad input: usage or config error (nothing was started). A fixture: the
// worst unit's (bench/session_judge.hpp). replay: 0 the raw CAN log rebuilds the record bit for
// bit, 1 it does not (the first difference, damage or divergence is printed), 4 not a session or
// no log.
#include <signal.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "app/cli_exit.hpp"
#include "app/closed_session_report.hpp"
#include "app/event_output.hpp"
#include "app/fixture_session.hpp"
#include "app/logging.hpp"
#include "app/memory_policy.hpp"
#include "app/panel/panel_server.hpp"
#include "app/prompt_answers.hpp"
#include "app/serial_check.hpp"
#include "app/session_folder.hpp"
#include "app/session_replay.hpp"
#include "app/session_upload.hpp"
#include "app/station_factory.hpp"
#include "app/tune_command.hpp"
#include "app/unit_history.hpp"
#include "hrgbench/analysis/estimate_report_json.hpp"
#include "hrgbench/analysis/session_judge.hpp"
#include "hrgbench/analysis/verdict_json.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/config/bench_configs.hpp"
#include "hrgbench/report/session_report.hpp"
#include "hrgbench/session/exit_codes.hpp"
#include "hrgbench/session/kill_point.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace {

using namespace hrgbench;

std::atomic<int> g_interrupts{0};
std::atomic<int> g_interrupt_signal{0};  // the first interrupt's signal, for the record

// First Ctrl-C (or SIGTERM): the session stops safely (table to zero, gyro stopped, record closed
// as ABORTED). Second: exit at once. Both are async-signal-safe (a lock-free atomic and _exit).
extern "C" void OnInterrupt(int signal) {
  int none = 0;
  g_interrupt_signal.compare_exchange_strong(none, signal);
  if (g_interrupts.fetch_add(1) >= 1) _exit(kExitAborted);
}

sigset_t InterruptSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

// main blocks SIGINT and SIGTERM before anything else (and the panel starts a session with them
// blocked, so from its exec on): an interrupt that comes before the handlers exist waits for them
// instead of killing the process by the default action, which left no record (issue 25 row 12).
void BlockInterrupts() {
  const sigset_t set = InterruptSignals();
  ::pthread_sigmask(SIG_BLOCK, &set, nullptr);
}
void UnblockInterrupts() {
  const sigset_t set = InterruptSignals();
  ::pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
}

// Then unblocks: a pending interrupt is delivered to the handler at once, and the session sees
// it at its first check (it stops safely and the record says so).
void InstallSignalHandlers() {
  struct sigaction action {};
  action.sa_handler = OnInterrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  UnblockInterrupts();
}

// A progress line on a terminal (rewritten in place), plain log lines otherwise.
class ProgressPrinter {
 public:
  ProgressPrinter() : tty_(::isatty(STDERR_FILENO) == 1) {}
  void operator()(const bench::Progress& p) {
    // An operator prompt waits on the terminal's last line: a progress line would overwrite it
    // (the prompt itself is logged).
    if (p.phase == "prompt") return;
    char line[200];
    if (p.phase == "estimate" || p.phase == "warm-up") {
      std::snprintf(line, sizeof line, "%-8.*s  %6.1f s elapsed  ~%6.1f s of free run ahead",
                    static_cast<int>(p.phase.size()), p.phase.data(), p.elapsed_s, p.remaining_s);
      Show(line, p);
      return;
    }
    const int written = std::snprintf(
        line, sizeof line,
        "run %d/%d  Ω %+.4g rad/s  %-8.*s  %6.1f s elapsed  ~%6.1f s left  %llu/%llu "
        "samples  %llu lost",
        p.run, p.run_count, p.omega_rad_s, static_cast<int>(p.phase.size()), p.phase.data(),
        p.elapsed_s, p.remaining_s, static_cast<unsigned long long>(p.samples),
        static_cast<unsigned long long>(p.samples_expected),
        static_cast<unsigned long long>(p.samples_lost));
    // A fixture: how many of its units are still in (the samples are theirs together).
    if (p.unit_count > 1 && written > 0 && static_cast<std::size_t>(written) < sizeof line)
      std::snprintf(line + written, sizeof line - static_cast<std::size_t>(written),
                    "  units %d/%d", p.units_active, p.unit_count);
    Show(line, p);
  }
  void Show(const char* line, const bench::Progress& p) {
    if (tty_) {
      std::fprintf(stderr, "\r%-150s", line);
      std::fflush(stderr);
      dirty_ = true;
    } else if (p.phase != last_phase_ || p.run != last_run_) {
      spdlog::info("{}", line);
    }
    last_phase_ = std::string(p.phase);
    last_run_ = p.run;
  }
  void Log(std::string_view text) {
    EndLine();
    spdlog::info("{}", text);
  }
  void EndLine() {
    if (dirty_) std::fputc('\n', stderr);
    dirty_ = false;
  }

 private:
  bool tty_;
  bool dirty_ = false;
  std::string last_phase_;
  int last_run_ = -1;
};

nlohmann::json ResultJson(const bench::SessionResult& result, const app::ClosedReport& report) {
  const std::string& report_path = report.path;
  nlohmann::json out;
  out["outcome"] = std::string(bench::ToString(result.outcome));
  out["exit_code"] = result.exit_code;
  out["reason"] = result.reason;
  out["session"] = result.dir.string();
  out["complete_runs"] = result.complete_runs;
  out["estimate"] = result.estimate_json;
  out["warnings"] = result.warnings;
  out["report"] = report_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(report_path);
  // A report still being written: the job writing it, and where it says how it went.
  out["report_job"] = report.job
                          ? nlohmann::json{{"pid", *report.job},
                                           {"state_file", app::ReportJobFile(result.dir).string()}}
                          : nlohmann::json(nullptr);
  // "limits" (each limit) predates "verdict" (the limits and the fit checks): both kept.
  if (result.verdict) {
    out["verdict"] = bench::VerdictJson(*result.verdict);
    out["limits"] = out["verdict"]["limits"];
  } else {
    out["verdict"] = nullptr;
    out["limits"] = nlohmann::json::array();
  }
  return out;
}

// `out`: stdout, or stderr when the events go to stdout (--events -: stdout is JSON lines only).
// The text result without the report's line: printed as soon as the session closes, so the
// operator reads the outcome while the report (and Chromium's PDF, seconds) is still being made.
void PrintOutcome(const bench::SessionResult& result, std::ostream& out_text) {
  if (result.estimate) out_text << result.estimate->Report();
  if (result.engineering) {
    out_text << "in the field's units (f0 = " << result.engineering->frequency_hz
             << " Hz as reported; angles on the shell):\n"
             << result.engineering->Report();
  }
  if (result.verdict) out_text << result.verdict->Report();
  for (const std::string& w : result.warnings) out_text << "warning: " << w << '\n';
  out_text << bench::ToString(result.outcome) << ": " << result.reason << '\n'
           << "session: " << result.dir.string() << std::endl;
}

// What follows the outcome once the report is written: its line, or the whole result as JSON.
void PrintReportLine(const bench::SessionResult& result, bool json, const app::ClosedReport& report,
                     std::ostream& out_text) {
  if (json)
    out_text << ResultJson(result, report).dump(1) << '\n';
  else if (!report.path.empty())
    out_text << "report: " << report.path << (report.job ? " (being written)" : "") << '\n';
}

// The report event: written (or none), or being written by a job.
void PublishReport(app::EventOutput& events, const app::ClosedReport& report) {
  if (report.job)
    events.publisher().ReportBeingWritten(report.path, *report.job);
  else
    events.publisher().ReportWritten(report.path);
}

// --events: where, and the queue's capacity (events).
// Who runs it and how the sequence's operator prompts are answered (--operator, --prompts).
struct OperatorRequest {
  std::string operator_id;  // empty: not recorded
  std::string prompts;      // --prompts as given (app/prompt_answers.hpp); empty: the default
};

struct EventsRequest {
  std::string target;  // empty: no event stream
  std::size_t capacity = bench::EventStream::kDefaultCapacity;
};

// What a session (one unit or a fixture) talks to besides its station: who answers its prompts,
// and its event stream when asked for one. Either cannot be opened: the reason is logged and the
// session refused before anything moves (kExitBadInput).
struct SessionChannels {
  std::unique_ptr<bench::PromptAnswers> answers;
  std::unique_ptr<app::EventOutput> event_output;  // null: no event stream
};

std::optional<SessionChannels> OpenSessionChannels(const bench::BenchConfigs& configs,
                                                   const OperatorRequest& who,
                                                   const EventsRequest& events) {
  SessionChannels channels;
  auto answers = app::OpenPromptAnswers(who.prompts, configs.sequence, who.operator_id);
  if (!answers) {
    spdlog::error("{}", answers.error());
    return std::nullopt;
  }
  channels.answers = std::move(*answers);
  if (!events.target.empty()) {
    auto opened = app::EventOutput::Open(events.target, events.capacity);
    if (!opened) {
      spdlog::error("{}", opened.error());
      return std::nullopt;
    }
    // A reader that goes away must cost events, not the process.
    ::signal(SIGPIPE, SIG_IGN);
    channels.event_output = std::move(*opened);
  }
  return channels;
}

int RunOrResume(const bench::BenchConfigs& configs, const std::string& dir,
                const std::string& serial, const OperatorRequest& who, bool resume, bool json,
                const EventsRequest& events, app::ReportMode report_mode) {
  auto channels = OpenSessionChannels(configs, who, events);
  if (!channels) return kExitBadInput;
  std::unique_ptr<app::EventOutput>& event_output = channels->event_output;
  auto station = app::OpenStation(configs.station);
  if (!station) {
    spdlog::error("{}", station.error());
    return kExitError;
  }
  ProgressPrinter printer;
  bench::RunnerOptions options;
  options.unit_serial = serial;
  options.operator_name = who.operator_id;
  options.prompts = channels->answers.get();
  options.software_version = HRGBENCH_SOFTWARE_VERSION;
  options.simulation = (*station)->simulation();
  options.interrupts = &g_interrupts;
  options.interrupt_signal = &g_interrupt_signal;
  options.on_progress = [&](const bench::Progress& p) { printer(p); };
  options.on_log = [&](std::string_view line) { printer.Log(line); };
  if (event_output) {
    event_output->publisher().SessionStarted(configs, resume ? app::RecordedSerial(dir) : serial,
                                             dir, resume, HRGBENCH_SOFTWARE_VERSION);
    event_output->publisher().Attach(options);
  }
  const bench::SessionResult result =
      resume ? bench::ResumeSession(configs, (*station)->hardware(), dir, options)
             : bench::RunSession(configs, (*station)->hardware(), dir, options);
  printer.EndLine();
  if (event_output) event_output->publisher().SessionFinished(result);
  std::ostream& out_text = events.target == "-" ? std::cerr : std::cout;
  if (!json) PrintOutcome(result, out_text);
  const app::ClosedReport report = app::MakeReports({result}, configs.station.results_url,
                                                    configs.station.report_paper, report_mode)
                                       .front();
  if (event_output) {
    PublishReport(*event_output, report);
    event_output->Close(result.dir);
  }
  // After the folder is complete (record closed, report written or started, events.json); never
  // changes the outcome.
  app::UploadClosedSession(configs.station.results_url, result.dir);
  PrintReportLine(result, json, report, out_text);
  return result.exit_code;
}

// What a kill during the report or the upload left undone for a session that closed with a
// verdict: the report when it is missing (and no job is writing it), the upload when it is not
// marked. The record is final: it is never re-opened or re-judged (the upload adds only its
// "results" mark).
app::ClosedReport FinishClosedFolder(const bench::SessionResult& result,
                                     const std::string& results_url, const std::string& paper,
                                     app::ReportMode report_mode) {
  const app::ClosedReport report = app::FinishReport(result, results_url, paper, report_mode);
  const auto recorded = session::ReadSessionRecord(result.dir);
  const bool marked = recorded && recorded->results.is_object() &&
                      recorded->results.value("uploaded", false) &&
                      recorded->results.value("url", std::string()) == results_url;
  if (!marked) app::UploadClosedSession(results_url, result.dir);
  return report;
}

// Every unit on the table in one session (a station with several fitted positions): the units'
// folders under `dir`, fixture.json beside them. `resume`: continues the units that did not close
// with a verdict; the others keep theirs.
int RunFixture(const bench::BenchConfigs& configs, const std::filesystem::path& dir,
               const app::FixtureRecord& record, const OperatorRequest& who, bool resume, bool json,
               const EventsRequest& events, app::ReportMode report_mode) {
  auto channels = OpenSessionChannels(configs, who, events);
  if (!channels) return kExitBadInput;
  std::unique_ptr<app::EventOutput>& event_output = channels->event_output;
  auto station = app::OpenStation(configs.station);
  if (!station) {
    spdlog::error("{}", station.error());
    return kExitError;
  }
  const bench::BenchHardware& all = (*station)->hardware();
  std::vector<bench::UnitSession> sessions = app::FixtureUnitSessions(record, dir);
  // The units this invocation drives: all of them, or on a resume those without a verdict, each
  // on the hardware of its recorded position.
  bench::BenchHardware hardware{all.table, all.clock, {}};
  std::vector<bench::UnitSession> driven;
  std::vector<std::size_t> driven_index;
  std::vector<std::optional<app::KeptVerdict>> kept(record.units.size());
  for (std::size_t i = 0; i < record.units.size(); ++i) {
    const auto at = std::find_if(all.units.begin(), all.units.end(), [&](const auto& unit) {
      return unit.position == record.units[i].position;
    });
    if (at == all.units.end()) {
      spdlog::error("{}: position '{}' of the fixture record is not fitted on station '{}'",
                    dir.string(), record.units[i].position, configs.station.name);
      return kExitBadInput;
    }
    if (resume && (kept[i] = app::ClosedVerdict(sessions[i].dir))) continue;
    sessions[i].simulation =
        (*station)->simulation(static_cast<std::size_t>(at - all.units.begin()));
    hardware.units.push_back(*at);
    driven.push_back(sessions[i]);
    driven_index.push_back(i);
  }
  if (!resume) {
    // Everything resume needs before fixture.json, the record that makes the folder a fixture's:
    // a kill at any point leaves a folder that is either resumable or plainly not started.
    if (auto saved = bench::SaveConfigs(configs, dir); !saved) {
      spdlog::error("{}", saved.error());
      return kExitBadInput;
    }
    session::KillPoint("fixture.config");
    if (auto written = app::WriteFixtureRecord(dir, record, {}, HRGBENCH_SOFTWARE_VERSION);
        !written) {
      spdlog::error("{}", written.error());
      return kExitBadInput;
    }
  }
  ProgressPrinter printer;
  bench::RunnerOptions options;
  options.software_version = HRGBENCH_SOFTWARE_VERSION;
  options.operator_name = who.operator_id;
  options.prompts = channels->answers.get();
  options.interrupts = &g_interrupts;
  options.interrupt_signal = &g_interrupt_signal;
  options.on_progress = [&](const bench::Progress& p) { printer(p); };
  options.on_log = [&](std::string_view line) { printer.Log(line); };
  // The event stream's units: every unit of the record (a resume's kept ones too), by index.
  nlohmann::json units = nlohmann::json::array();
  for (const app::FixtureUnit& unit : record.units)
    units.push_back(
        {{"position", unit.position}, {"serial", unit.serial}, {"session", unit.folder}});
  if (event_output) {
    event_output->publisher().SessionStarted(configs, "fixture", dir.string(), resume,
                                             HRGBENCH_SOFTWARE_VERSION);
    event_output->publisher().FixtureStarted(units);
    // The sequencer numbers the units it drives; the stream numbers the record's.
    nlohmann::json driven_units = nlohmann::json::array();
    for (const std::size_t i : driven_index) driven_units.push_back(units[i]);
    event_output->publisher().AttachFixture(options, driven_units);
  }
  std::vector<bench::SessionResult> ran;
  if (!driven.empty()) {
    ran = resume ? bench::ResumeSessions(configs, hardware, driven, options)
                 : bench::RunSessions(configs, hardware, driven, options);
  }
  printer.EndLine();
  // Every unit's result: this invocation's, or (resume) the verdict its session already had.
  std::vector<bench::SessionResult> results(record.units.size());
  std::vector<app::ClosedReport> reports(record.units.size());
  std::vector<bench::SessionResult> this_run;  // the units driven now: their reports together
  for (std::size_t i = 0; i < record.units.size(); ++i) {
    results[i].dir = sessions[i].dir;
    const auto k = std::find(driven_index.begin(), driven_index.end(), i);
    if (k != driven_index.end()) {
      results[i] = ran[static_cast<std::size_t>(k - driven_index.begin())];
      this_run.push_back(results[i]);
      continue;
    }
    if (kept[i]) {
      results[i].outcome = kept[i]->pass ? bench::OutcomeKind::kPass : bench::OutcomeKind::kFail;
      results[i].exit_code = bench::ExitCode(results[i].outcome);
      results[i].reason = bench::KeptReason(kept[i]->reason);
      reports[i] = FinishClosedFolder(results[i], configs.station.results_url,
                                      configs.station.report_paper, report_mode);
    }
  }
  const std::vector<app::ClosedReport> made = app::MakeReports(
      this_run, configs.station.results_url, configs.station.report_paper, report_mode);
  for (std::size_t j = 0; j < driven_index.size(); ++j) {
    reports[driven_index[j]] = made[j];
    app::UploadClosedSession(configs.station.results_url, this_run[j].dir);
  }
  if (auto written = app::WriteFixtureRecord(dir, record, results, HRGBENCH_SOFTWARE_VERSION);
      !written)
    spdlog::error("{}", written.error());
  // The worst unit's (ABORTED over ERROR over FAIL over PASS).
  std::vector<bench::OutcomeKind> outcomes;
  for (const bench::SessionResult& result : results) outcomes.push_back(result.outcome);
  const int code = bench::FixtureExitCode(outcomes);
  if (event_output) {
    std::string reason;
    for (std::size_t i = 0; i < results.size(); ++i) {
      event_output->publisher().UnitFinished(i, results[i], reports[i].path);
      reason += (reason.empty() ? "" : ", ") + record.units[i].position + " " +
                std::string(bench::ToString(results[i].outcome));
    }
    event_output->publisher().FixtureFinished(bench::FixtureOutcome(outcomes), code,
                                              std::to_string(results.size()) + " units: " + reason,
                                              dir.string());
    event_output->Close(dir);
  }
  if (json) {
    nlohmann::json out;
    out["fixture"] = dir.string();
    out["exit_code"] = code;
    out["units"] = nlohmann::json::array();
    for (std::size_t i = 0; i < results.size(); ++i) {
      nlohmann::json unit = ResultJson(results[i], reports[i]);
      unit["position"] = record.units[i].position;
      unit["serial"] = record.units[i].serial;
      out["units"].push_back(std::move(unit));
    }
    std::cout << out.dump(1) << '\n';
    return code;
  }
  for (std::size_t i = 0; i < results.size(); ++i) {
    std::cout << record.units[i].position << "  " << record.units[i].serial << "  "
              << bench::ToString(results[i].outcome) << ": " << results[i].reason << '\n'
              << "    session: " << results[i].dir.string() << '\n';
    if (!reports[i].path.empty())
      std::cout << "    report: " << reports[i].path << (reports[i].job ? " (being written)" : "")
                << '\n';
  }
  std::cout << "fixture: " << dir.string() << '\n';
  return code;
}

// `hrg-bench replay FIXTURE [--unit POSITION|SERIAL]`: each unit's session replayed in turn (or
// the one named); exit kExitOk when every one is identical, kExitFail otherwise, kExitBadInput
// when the record is not read.
int ReplayFixture(const std::filesystem::path& dir, const std::string& unit, bool estimate,
                  const std::string& rebuild_into, bool json) {
  auto record = app::ReadFixtureRecord(dir);
  if (!record) {
    std::cerr << record.error() << '\n';
    return kExitBadInput;
  }
  std::vector<app::FixtureUnit> chosen;
  for (const app::FixtureUnit& u : record->units) {
    if (unit.empty() || u.position == unit || u.serial == unit) chosen.push_back(u);
  }
  if (chosen.empty()) {
    std::cerr << "--unit " << unit << ": no such position or serial in " << dir.string() << '\n';
    return kExitBadInput;
  }
  if (!rebuild_into.empty() && chosen.size() != 1) {
    std::cerr << "--rebuild-into: rebuilds one unit's session; name it with --unit\n";
    return kExitBadInput;
  }
  nlohmann::json out{{"fixture", dir.string()}, {"units", nlohmann::json::array()}};
  bool identical = true;
  for (const app::FixtureUnit& u : chosen) {
    app::ReplayOptions options;
    options.estimate = estimate;
    options.rebuild_into = rebuild_into;
    auto replayed = app::ReplaySession(dir / u.folder, options);
    if (!replayed) {
      std::cerr << replayed.error() << '\n';
      return kExitBadInput;
    }
    identical = identical && replayed->Identical();
    if (json) {
      nlohmann::json one = app::ReplayJson(*replayed);
      one["position"] = u.position;
      one["serial"] = u.serial;
      out["units"].push_back(std::move(one));
    } else {
      std::cout << "== " << u.position << "  " << u.serial << '\n' << app::ReplayText(*replayed);
    }
  }
  if (json) {
    out["identical"] = identical;
    std::cout << out.dump(1) << '\n';
  }
  return identical ? kExitOk : kExitFail;
}

// `hrg-bench run`'s command line.
struct RunArgs {
  std::string station, sequence, limits, out_dir;
  OperatorRequest who;
  std::vector<std::string> serials;
  bool tune = false;  // a PASS unit tuned at once (`hrg-bench tune DIR` with its defaults)
};

// `hrg-bench replay`'s command line.
struct ReplayArgs {
  std::string dir;
  bool no_estimate = false;
  std::string unit;
  std::string rebuild_into;
};

// `hrg-bench check`'s command line.
struct CheckArgs {
  std::string station, sequence, limits;
};

// `hrg-bench serve`: the operator panel until the first interrupt.
int Serve(app::PanelOptions panel, const char* argv0) {
  std::error_code ec;
  panel.program = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) panel.program = argv0;
  InstallSignalHandlers();
  ::signal(SIGPIPE, SIG_IGN);  // a browser that goes away is a failed write, not a signal
  return app::RunPanel(panel, g_interrupts);
}

// `hrg-bench replay DIR`: one unit's session, or a fixture's (ReplayFixture).
int Replay(const ReplayArgs& args, bool json) {
  if (app::IsFixtureFolder(args.dir)) {
    return ReplayFixture(args.dir, args.unit, !args.no_estimate, args.rebuild_into, json);
  }
  if (!args.unit.empty()) {
    std::cerr << "--unit: " << args.dir << " is one unit's session, not a fixture's\n";
    return kExitBadInput;
  }
  app::ReplayOptions options;
  options.estimate = !args.no_estimate;
  options.rebuild_into = args.rebuild_into;
  auto replayed = app::ReplaySession(args.dir, options);
  if (!replayed) {
    std::cerr << replayed.error() << '\n';
    return kExitBadInput;
  }
  if (json) {
    std::cout << app::ReplayJson(*replayed).dump(1) << '\n';
  } else {
    std::cout << app::ReplayText(*replayed);
  }
  return replayed->Identical() ? kExitOk : kExitFail;
}

// `hrg-bench check S.toml Q.toml [L.toml]`: the configs loaded and cross-checked, the planned bus
// load printed; nothing started.
int Check(const CheckArgs& args) {
  auto configs = bench::LoadBenchConfigs(args.station, args.sequence, args.limits);
  if (!configs) {
    std::cerr << configs.error().ToString() << '\n';
    return kExitBadInput;
  }
  std::cout << "ok: station '" << configs->station.name << "', sequence '" << configs->sequence.name
            << "' (" << configs->sequence.runs.size() << " runs, "
            << configs->sequence.TotalFreeRunS() << " s of free run)"
            << (configs->limits.file.empty() ? "" : ", limits '" + configs->limits.name + "'")
            << '\n';
  const bench::PlannedBusLoad bus = bench::BusiestRunLoad(*configs);
  std::cout << "gyro bus: " << bus.bus << ", at most " << bench::Percent(bus.load.bus_share)
            << " busy (" << bus.sample_rate_hz << " samples/s" << (bus.units > 1 ? " per unit" : "")
            << ", " << static_cast<long long>(bus.load.frames_per_s)
            << " frames/s, worst-case stuffing; planned maximum "
            << bench::Percent(hw::kMaxPlannedBusShare) << ")\n";
  const std::vector<bench::PlannedBusLoad> buses = bench::EachBusLoad(*configs);
  if (buses.size() > 1) {
    for (const bench::PlannedBusLoad& each : buses) {
      std::string positions;
      for (const std::string& name : each.positions)
        positions += (positions.empty() ? "" : ", ") + name;
      std::cout << "  " << each.bus << ": " << positions << ", at most "
                << bench::Percent(each.load.bus_share) << " busy\n";
    }
  }
  return kExitOk;
}

// `hrg-bench run` on a station with several fitted positions: one session per unit under a new
// fixture folder.
int RunFixtureCommand(const bench::BenchConfigs& configs, const RunArgs& args, bool json,
                      const EventsRequest& events, app::ReportMode report_mode) {
  auto record = app::PlanFixture(configs.station, args.serials);
  if (!record) {
    std::cerr << record.error() << '\n';
    return kExitBadInput;
  }
  record->config_sha256 = {
      {"station", configs.station.sha256_hex},
      {"sequence", configs.sequence.sha256_hex},
      {"limits", configs.limits.sha256_hex.empty() ? nlohmann::json(nullptr)
                                                   : nlohmann::json(configs.limits.sha256_hex)}};
  std::filesystem::path dir = args.out_dir;
  if (dir.empty()) {
    const auto folder = app::NewSessionFolder("sessions", "fixture", std::time(nullptr));
    if (!folder) {
      std::cerr << folder.error() << '\n';
      return kExitBadInput;
    }
    dir = *folder;
  }
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_empty(dir, ec)) {
    std::cerr << dir.string() << ": not empty; a fixture session needs a new folder\n";
    return kExitBadInput;
  }
  return RunFixture(configs, dir, *record, args.who, false, json, events, report_mode);
}

// `hrg-bench run`: a new session of one unit, or of a fixture's.
int Run(const RunArgs& args, bool json, const EventsRequest& events, app::ReportMode report_mode) {
  auto configs = bench::LoadBenchConfigs(args.station, args.sequence, args.limits);
  if (!configs) {
    std::cerr << configs.error().ToString() << '\n';
    return kExitBadInput;
  }
  if (!args.who.operator_id.empty()) {
    if (auto problem = app::OperatorProblem(args.who.operator_id)) {
      std::cerr << "--operator: " << *problem << '\n';
      return kExitBadInput;
    }
  }
  if (bench::FittedPositions(configs->station).size() > 1) {
    if (args.tune) {
      std::cerr << "--tune: tunes one unit's session; tune a fixture's units with hrg-bench tune "
                   "UNIT_DIR each\n";
      return kExitBadInput;
    }
    return RunFixtureCommand(*configs, args, json, events, report_mode);
  }
  if (args.serials.size() != 1) {
    std::cerr << "--serial: " << args.serials.size() << " serials for station '"
              << configs->station.name << "', which has one fitted position\n";
    return kExitBadInput;
  }
  const std::string& serial = args.serials.front();
  // One rule for a serial wherever it comes from (the panel checks the same).
  if (auto problem = app::SerialProblem(serial)) {
    std::cerr << "--serial: " << *problem << '\n';
    return kExitBadInput;
  }
  std::string dir = args.out_dir;
  if (dir.empty()) {
    const auto folder = app::NewSessionFolder("sessions", serial, std::time(nullptr));
    if (!folder) {
      std::cerr << folder.error() << '\n';
      return kExitBadInput;
    }
    dir = folder->string();
  }
  // With --tune the report is made once, after the tuning (its section included).
  const int exit_code = RunOrResume(*configs, dir, serial, args.who, false, json, events,
                                    args.tune ? app::ReportMode::kNone : report_mode);
  if (!args.tune) return exit_code;
  if (exit_code != kExitOk || g_interrupts.load() > 0) {  // not tuned: the session's report
    const std::string html = app::ReportTunedSession(dir, *configs, report_mode);
    if (!json && !html.empty()) std::cout << "report: " << html << '\n';
    return exit_code;
  }
  // The unit passed: its compensation, written and verified, in one command (issue 28).
  app::TuneOptions tune;
  tune.dir = dir;
  tune.json = json;
  tune.interrupts = &g_interrupts;
  tune.report = report_mode;
  return app::Tune(tune);
}

// `hrg-bench resume DIR` of a session that closed as PASS or FAIL (killed during its report or
// upload): the verdict stands and session.json is not rewritten; only the report and the upload
// are finished.
int FinishClosed(const std::filesystem::path& dir, bool json, const EventsRequest& events,
                 app::ReportMode report_mode) {
  const auto recorded = session::ReadSessionRecord(dir);
  if (!recorded || !recorded->outcome) {
    std::cerr << dir.string() << ": cannot read the closed record again\n";
    return kExitBadInput;
  }
  if (!events.target.empty())
    spdlog::info("--events: {} is closed; nothing runs, so no events are written", dir.string());
  bench::SessionResult result;
  result.dir = dir;
  result.outcome = recorded->outcome->kind;
  result.exit_code = bench::ExitCode(result.outcome);
  result.reason = bench::KeptReason(recorded->outcome->reason);
  result.estimate_json = recorded->outcome->estimate_json;
  for (const session::RunRecord& run : recorded->runs)
    result.complete_runs += run.status == bench::kRunComplete ? 1 : 0;
  std::string results_url, paper = "a4";
  if (auto configs = bench::LoadSavedConfigs(dir)) {
    results_url = configs->station.results_url;
    paper = configs->station.report_paper;
  } else {
    spdlog::warn("{}; the session is not uploaded", configs.error());
  }
  spdlog::info("{}: closed as {}; its record is kept as it is", dir.string(),
               bench::ToString(result.outcome));
  std::ostream& out_text = events.target == "-" ? std::cerr : std::cout;
  if (!json) PrintOutcome(result, out_text);
  const app::ClosedReport report = FinishClosedFolder(result, results_url, paper, report_mode);
  PrintReportLine(result, json, report, out_text);
  return result.exit_code;
}

// `hrg-bench resume DIR`: an interrupted session continued, or a fixture's units without a
// verdict.
int Resume(const std::string& resume_dir, const OperatorRequest& who, bool json,
           const EventsRequest& events, app::ReportMode report_mode) {
  const std::filesystem::path dir = resume_dir;
  if (!who.operator_id.empty()) {
    if (auto problem = app::OperatorProblem(who.operator_id)) {
      std::cerr << "--operator: " << *problem << '\n';
      return kExitBadInput;
    }
  }
  if (app::IsFixtureFolder(dir)) {
    auto record = app::ReadFixtureRecord(dir);
    if (!record) {
      std::cerr << record.error() << '\n';
      return kExitBadInput;
    }
    auto configs = app::FixtureConfigs(dir, *record);
    if (!configs) {
      std::cerr << configs.error() << '\n';
      return kExitBadInput;
    }
    return RunFixture(*configs, dir, *record, who, true, json, events, report_mode);
  }
  if (auto problem = app::NotStartedProblem(dir)) {
    std::cerr << *problem << '\n';
    return kExitBadInput;
  }
  if (app::ClosedVerdict(dir)) return FinishClosed(dir, json, events, report_mode);
  auto configs = bench::LoadSavedConfigs(dir);
  if (!configs) {
    std::cerr << configs.error() << '\n';
    return kExitBadInput;
  }
  return RunOrResume(*configs, resume_dir, "", who, true, json, events, report_mode);
}

// --events and --events-queue on `run` and `resume`.
void AddEventsOptions(CLI::App* command, EventsRequest& events) {
  command->add_option("--events", events.target,
                      "write the session's events, one JSON object per line, to FILE or - "
                      "(stdout; not with --json)");
  command
      ->add_option("--events-queue", events.capacity,
                   "events held for a slow reader before they are dropped (and counted)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 20));
}

// --report on `run`, `resume` and `tune`.
void AddReportOption(CLI::App* command, std::string& mode) {
  command
      ->add_option("--report", mode,
                   "the report once the session is closed: wait (written before the program "
                   "exits; default), background (a report job of its own follows the program's "
                   "exit: report/job.json says how it goes), none (hrg-report SESSION makes it "
                   "later)")
      ->check(CLI::IsMember({"wait", "background", "none"}));
}

// --prompts on `run` and `resume`.
void AddPromptsOption(CLI::App* command, OperatorRequest& who) {
  command->add_option("--prompts", who.prompts,
                      "who answers the sequence's operator prompts: terminal (default when stdin "
                      "is one), confirm (every prompt confirmed, recorded as auto), fd:N (JSON "
                      "lines from the panel)");
}

CLI::App* AddRunCommand(CLI::App& cli, RunArgs& args, bool& json, EventsRequest& events,
                        std::string& report) {
  CLI::App* run = cli.add_subcommand("run", "run a session");
  run->add_option("--station", args.station, "station config (TOML)")->required();
  run->add_option("--sequence", args.sequence, "sequence config (TOML)")->required();
  run->add_option("--limits", args.limits, "limits config (TOML) for the verdict");
  run->add_option("--serial", args.serials,
                  "unit serial number; on a fixture of N positions, one per fitted position in "
                  "order, or POSITION=SERIAL")
      ->required();
  run->add_option("-o,--output", args.out_dir,
                  "session directory (default sessions/SERIAL-UTC; a fixture's: "
                  "sessions/fixture-UTC)");
  run->add_option("--operator", args.who.operator_id,
                  "who runs the session (an operator id, typed or scanned): recorded as the "
                  "session's operator");
  AddPromptsOption(run, args.who);
  run->add_flag("--json", json, "print the result as one JSON object");
  AddEventsOptions(run, events);
  AddReportOption(run, report);
  run->add_flag("--tune", args.tune,
                "a unit that passes is tuned at once: its compensation written, refined and "
                "verified on the table (hrg-bench tune DIR; one unit's station)");
  return run;
}

CLI::App* AddResumeCommand(CLI::App& cli, std::string& dir, OperatorRequest& who, bool& json,
                           EventsRequest& events, std::string& report) {
  CLI::App* resume = cli.add_subcommand("resume", "continue an interrupted session");
  resume->add_option("dir", dir, "session directory")->required();
  resume->add_option("--operator", who.operator_id,
                     "who resumes it: recorded in the record's resumed_at (and as its operator "
                     "when the start recorded none)");
  AddPromptsOption(resume, who);
  resume->add_flag("--json", json, "print the result as one JSON object");
  AddEventsOptions(resume, events);
  AddReportOption(resume, report);
  return resume;
}

CLI::App* AddCheckCommand(CLI::App& cli, CheckArgs& args) {
  CLI::App* check = cli.add_subcommand("check", "validate configs only");
  check->add_option("station", args.station, "station config")->required();
  check->add_option("sequence", args.sequence, "sequence config")->required();
  check->add_option("limits", args.limits, "limits config");
  return check;
}

CLI::App* AddReplayCommand(CLI::App& cli, ReplayArgs& args, bool& json) {
  CLI::App* replay = cli.add_subcommand(
      "replay", "play a session's raw CAN log back through the gyro driver and compare");
  replay->add_option("dir", args.dir, "session directory")->required();
  replay->add_flag("--json", json, "print the comparison as one JSON object");
  replay->add_flag("--no-estimate", args.no_estimate,
                   "compare the samples only, not the estimate made from them");
  replay->add_option("--unit", args.unit,
                     "a fixture's folder: replay only this unit (its position or its serial)");
  replay->add_option("--rebuild-into", args.rebuild_into,
                     "write a new session folder whose complete runs are rebuilt from the log "
                     "(restores a lost or damaged run file)");
  return replay;
}

CLI::App* AddTuneCommand(CLI::App& cli, app::TuneOptions& tune, std::string& report) {
  CLI::App* command = cli.add_subcommand(
      "tune",
      "a unit's PASS session made into its compensation, written to its electronics, refined "
      "and verified on the table (DIR/tune.json)");
  command->add_option("dir", tune.dir, "the unit's closed session folder")->required();
  command
      ->add_option("--rates", tune.rates_rad_s,
                   "the verification's table rates, rad/s, both signs (default 0.3 -0.3)")
      ->check(CLI::Range(-10.0, 10.0))
      ->expected(2, 16);
  command
      ->add_option("--verify-turns", tune.verify_turns, "turns of the wave per verification hold")
      ->check(CLI::Range(0.5, 100.0));
  command->add_option("--refine-turns", tune.refine_turns, "turns of the wave per refinement hold")
      ->check(CLI::Range(0.5, 100.0));
  command->add_option("--sample-rate", tune.sample_rate_hz, "the angle output's rate, Hz")
      ->check(CLI::Range(10u, 2000u));
  command
      ->add_option("--zero-rate-hold", tune.zero_rate_hold_s,
                   "seconds at zero rate after the verification: the Allan deviation (ARW, bias "
                   "instability)")
      ->check(CLI::Range(0.0, 3600.0));
  command->add_flag("--json", tune.json, "print tune.json");
  AddReportOption(command, report);  // the session's report, made again with the tuning
  return command;
}

CLI::App* AddServeCommand(CLI::App& cli, app::PanelOptions& panel) {
  CLI::App* serve = cli.add_subcommand("serve", "the operator panel in the browser");
  serve
      ->add_option("--station", panel.station,
                   "station config (TOML); the sequence-*.toml and "
                   "limits-*.toml beside it are the ones offered")
      ->required();
  serve->add_option("--listen", panel.listen, "HOST:PORT (default 127.0.0.1:8080)");
  serve->add_option("--sessions", panel.sessions, "sessions folder (default sessions)");
  serve->add_option("--token-file", panel.token_file,
                    "access token (required to listen on another address than localhost)");
  return serve;
}

}  // namespace

int main(int argc, char** argv) {
  BlockInterrupts();  // first: see BlockInterrupts
  hrgbench::app::KeepFreedMemoryForReuse();
  CLI::App cli{
      "hrg-bench: free-run sessions of a hemispherical resonator gyro on a rate table, recorded, "
      "estimated and judged.\n"
      "run, resume: the session's outcome (a fixture: its worst unit's). replay: 1 the log does "
      "not rebuild the record. check, serve: 4 a config or option refused; serve: 2 the port is "
      "taken. tune: the tuning's verdict (0 PASS, 1 FAIL, 2 ERROR, 3 ABORTED).\n" +
      std::string(kExitCodesHelp)};
  cli.require_subcommand(1);
  bool quiet = false;
  bool json = false;
  app::AddCommonFlags(cli, &quiet);
  RunArgs run_args;
  std::string resume_dir;
  OperatorRequest resume_who;
  CheckArgs check_args;
  ReplayArgs replay_args;
  app::PanelOptions panel;
  EventsRequest events;
  std::string report = "wait";
  CLI::App* run = AddRunCommand(cli, run_args, json, events, report);
  CLI::App* resume = AddResumeCommand(cli, resume_dir, resume_who, json, events, report);
  CLI::App* check = AddCheckCommand(cli, check_args);
  CLI::App* replay = AddReplayCommand(cli, replay_args, json);
  CLI::App* serve = AddServeCommand(cli, panel);
  app::TuneOptions tune;
  tune.interrupts = &g_interrupts;
  CLI::App* tune_command = AddTuneCommand(cli, tune, report);

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app::ExitForParseError(cli, error);
  }
  app::SetUpStderrLogging("hrg-bench", quiet ? -1 : 0);
  if (events.target == "-" && json) {
    std::cerr << "--events - and --json both write to stdout: send the events to a file\n";
    return kExitBadInput;
  }
  // run and resume: the handlers before anything that takes time (configs, the station, the
  // event pipe), so that an early interrupt is the session's first check and a second one exits.
  // The other commands keep the default dispositions.
  if (*run || *resume || *tune_command)
    InstallSignalHandlers();
  else if (!*serve)
    UnblockInterrupts();
  try {
    if (*serve) return Serve(panel, argv[0]);
    if (*replay) return Replay(replay_args, json);
    if (*check) return Check(check_args);
    const app::ReportMode report_mode = *app::ParseReportMode(report);  // CLI11 checked it
    if (*tune_command) {
      tune.report = report_mode;
      return app::Tune(tune);
    }
    if (*run) return Run(run_args, json, events, report_mode);
    if (*resume) return Resume(resume_dir, resume_who, json, events, report_mode);
    return kExitBadInput;  // require_subcommand(1): not reached
  } catch (const std::exception& error) {
    spdlog::critical("unexpected failure: {}", error.what());
    return kExitError;
  }
}
