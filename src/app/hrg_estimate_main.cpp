// hrg-estimate DIR: estimates δ and ξ from a session, as a readable report or one JSON object.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <string>

#include "app/cli_exit.hpp"
#include "app/logging.hpp"
#include "app/memory_policy.hpp"
#include "hrgbench/analysis/engineering_of_record.hpp"
#include "hrgbench/analysis/estimate_method.hpp"
#include "hrgbench/analysis/estimate_report_json.hpp"
#include "hrgbench/analysis/output_filter.hpp"
#include "hrgbench/analysis/recorded_frequency.hpp"
#include "hrgbench/analysis/recorded_runs.hpp"
#include "hrgbench/session/run_spool.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace {

using namespace hrgbench;

// The runs' samples kept in memory between the fit's passes: a production session (6 × 100 s at
// 1 kHz, 24 MB) and one of 6 × 1000 s (240 MB) fit whole; longer ones are spooled beyond it
// (session/run_spool.hpp).
constexpr std::size_t kDefaultMemoryMib = 1024;
constexpr std::size_t kMaxMemoryMib = std::size_t{1} << 20;

struct Arguments {
  std::string dir;
  std::string method = "ml";
  std::string xi;  // empty: the method's default
  bool json = false;
  int phase_degree = estimator::MlOptions{}.phase_degree;
  bool omega_exact = false;
  std::string covariance = "auto";
  std::size_t memory_mib = kDefaultMemoryMib;
};

int Run(const Arguments& args) {
  bench::MethodRequest request;
  request.method = *bench::ParseMethod(args.method);  // CLI11 checked membership
  if (!args.xi.empty()) request.xi = bench::ParseXiSet(args.xi);
  request.phase_degree = args.phase_degree;
  request.omega_uncertainty = !args.omega_exact;
  request.covariance = *bench::ParseCovariance(args.covariance);  // CLI11 checked membership
  if (const std::string problem = bench::CheckRequest(request); !problem.empty()) {
    spdlog::error("{}", problem);
    return kExitBadInput;
  }

  session::ReadOptions read_options;
  read_options.min_samples_per_run = bench::MinimumSamples(request.method);
  read_options.extra_columns = false;  // the estimate reads t_s and y only
  read_options.load_samples = false;   // the runs are read one by one into the spool below
  auto session = session::ReadSession(args.dir, read_options);
  if (!session) {
    // The message alone on stderr, unadorned, so scripts can match it (it names the file).
    std::cerr << session.error().ToString() << '\n';
    return kExitBadInput;
  }
  // The same document typed by the record's one reader: the electronics' declaration, the runs'
  // plans and f0 (a malformed declaration is named here, by field and value).
  const auto record = session::ReadSessionRecord(session->document,
                                                 std::filesystem::path(args.dir) / "session.json");
  if (!record) {
    std::cerr << record.error().ToString() << '\n';
    return kExitBadInput;
  }
  // In the model's I/Q convention, less the output filter's settling after release; read run by
  // run into the spool, which keeps --memory-mib of them in memory and the rest in a scratch file.
  session::RunSpool runs(args.memory_mib << 20);
  const auto spooled =
      bench::SpoolRecordedRuns(args.dir, *session, record->electronics, read_options, &runs);
  if (!spooled) {
    std::cerr << spooled.error().ToString() << '\n';
    // A run's file is bad input; the scratch file failing (disk full) is this program's error.
    const auto file = spooled.error().file.lexically_normal().string();
    const auto dir = std::filesystem::path(args.dir).lexically_normal().string();
    return file.starts_with(dir) ? kExitBadInput : kExitError;
  }
  const bench::PreparedRuns& prepared = *spooled;
  if (runs.size() == 0) {
    std::cerr << args.dir << ": no complete run to estimate from\n";
    return kExitBadInput;
  }
  // The noise shape the station declared for this session's electronics (white when none).
  auto noise_shape = bench::RecordedNoiseShape(record->electronics, session->sample_rate_hz);
  if (!noise_shape) {
    std::cerr << (std::filesystem::path(args.dir) / "session.json").string() << ": "
              << noise_shape.error() << '\n';
    return kExitBadInput;
  }
  request.noise_shape = std::move(*noise_shape);
  const session::RunSpool::Counts spool = runs.counts();
  spdlog::debug("{}: {} runs loaded ({} kept in memory, {} spooled: {} MB), method {}", args.dir,
                runs.size(), spool.kept_runs, spool.spooled_runs, spool.bytes_written >> 20,
                args.method);

  bench::MethodResult result = bench::RunMethod(runs, request);
  bench::NameIqConventionContradiction(*record, &result.summary);
  std::vector<std::string> warnings = result.selection_warnings;
  warnings.insert(warnings.end(), session->warnings.begin(), session->warnings.end());

  if (args.json) {
    nlohmann::json report =
        bench::EstimateReportJson(args.method, result.summary, warnings, *record);
    report["preparation"] = prepared.Json();
    std::cout << report.dump(1) << '\n';
  } else {
    std::cout << "session: " << args.dir << " (" << runs.size() << " runs)\n";
    for (const std::string& w : warnings) std::cout << "warning: " << w << '\n';
    for (const std::string& n : prepared.notes) std::cout << "note: " << n << '\n';
    std::cout << result.summary.Report();
    if (!result.summary.Report().ends_with('\n')) std::cout << '\n';
    if (result.summary.IsUsable()) {
      const bench::EngineeringOfRecord engineering =
          bench::ComputeEngineeringOfRecord(result.summary, *record);
      for (const std::string& n : engineering.notes) std::cout << "note: " << n << '\n';
      std::cout << "in the field's units (f0: " << engineering.frequency_source
                << "; angles on the shell):\n"
                << engineering.quantities.Report() << "uncertainty budgets:\n"
                << engineering.quantities.BudgetReport();
    }
    std::cout << "time: " << result.seconds << " s\n";
  }
  if (!result.summary.IsUsable()) {
    spdlog::error("estimate not usable: {}: {}", estimator::ToString(result.summary.termination),
                  result.summary.message);
    return kExitFail;
  }
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  hrgbench::app::KeepFreedMemoryForReuse();  // first: before any thread
  CLI::App cli{
      "hrg-estimate: estimate the HRG parameters delta (6) and xi (4) from a session directory.\n"
      "Methods: ml (output-error maximum likelihood, the default), paper (the paper's OLS on "
      "numerical derivatives, xi ignored), paper-xi-grid (the paper's xi1 grid search).\n"
      "--xi (ml only): none | xi1 | all; default: all four when the runs' rates make them "
      "identifiable, else the largest identifiable set (with a warning).\n"
      "Here 1: estimate not usable (numerical failure, not identifiable); 4: bad command line or "
      "malformed session (the reason on stderr, nothing on stdout).\n" +
      std::string(hrgbench::kExitCodesHelp)};
  Arguments args;
  bool quiet = false;
  cli.add_option("dir", args.dir, "session directory (session.json + runs/)")->required();
  cli.add_option("--method", args.method, "ml | paper | paper-xi-grid")
      ->check(CLI::IsMember({"ml", "paper", "paper-xi-grid"}));
  cli.add_option("--xi", args.xi, "which xi to estimate: none | xi1 | all")
      ->check(CLI::IsMember({"none", "xi1", "all"}));
  cli.add_flag("--json", args.json, "print one JSON object on stdout instead of the report");
  cli.add_option("--phase-degree", args.phase_degree,
                 "ml: degree of each run's common phase nuisance (0 = the demodulation reference "
                 "is the wave's phase, 1 = plus a frequency offset, 2 = plus a frequency ramp; "
                 "default 2)")
      ->check(CLI::Range(0, 3));
  cli.add_flag("--omega-exact", args.omega_exact,
               "ml: take each run's recorded rate as exact (ignore its recorded standard error)");
  cli.add_option("--covariance", args.covariance,
                 "ml: auto (white-noise covariance, the sandwich when residuals are not white) | "
                 "white | sandwich")
      ->check(CLI::IsMember({"auto", "white", "sandwich"}));
  cli.add_option("--memory-mib", args.memory_mib,
                 "the runs' samples kept in memory, MiB (default " +
                     std::to_string(kDefaultMemoryMib) +
                     "); runs beyond it are written to a scratch file in TMPDIR and read back on "
                     "each pass of the fit (0: only the runs in use, one per thread)")
      ->check(CLI::Range(std::size_t{0}, kMaxMemoryMib));
  hrgbench::app::AddCommonFlags(cli, &quiet);
  return hrgbench::app::ParseAndRun(cli, argc, argv, "hrg-estimate", quiet,
                                    [&] { return Run(args); });
}
