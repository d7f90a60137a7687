// hrg-sim SPEC.toml -o DIR: simulates the runs of a spec and writes them as a session, with the
// truth and the provenance in session.json.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>

#include "app/cli_exit.hpp"
#include "app/logging.hpp"
#include "app/sim_session.hpp"
#include "hrgbench/config/sha256.hpp"
#include "hrgbench/config/sim_spec.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace {

using namespace hrgbench;

int Run(const std::filesystem::path& spec_path, const std::filesystem::path& out_dir, bool force) {
  auto spec = app::LoadSimSpec(spec_path);
  if (!spec) {
    spdlog::error("{}", spec.error().ToString());
    return kExitBadInput;
  }
  auto sha = config_file::Sha256FileHex(spec_path);
  if (!sha) {
    spdlog::error("{}", sha.error());
    return kExitBadInput;
  }
  for (const auto& run : spec->runs) {
    if (run.sample_rate_hz != spec->runs.front().sample_rate_hz) {
      spdlog::warn(
          "runs have different sample rates; session.json records the first run's ({} Hz), "
          "the per-run rates are in \"simulation\"",
          spec->runs.front().sample_rate_hz);
      break;
    }
  }

  estimator::SimulationOptions options;
  options.delta = spec->delta;
  options.xi = spec->xi;
  options.sigma = spec->sigma;
  options.seed = spec->seed;
  std::string why;
  const std::vector<estimator::RunData> runs = estimator::SimulateRuns(spec->runs, options, &why);
  if (runs.size() != spec->runs.size()) {
    spdlog::error("{}: simulation failed: {}", spec_path.string(), why);
    return kExitFail;
  }

  const session::Session session =
      app::MakeSimSession(*spec, runs, {HRGBENCH_SOFTWARE_VERSION, *sha});
  if (auto written = app::WriteSimSession(out_dir, session, runs, force); !written) {
    spdlog::error("{}", written.error());
    // A non-empty directory without --force is the operator's input; an I/O failure is not.
    return written.error().find("--force") != std::string::npos ? kExitBadInput : kExitFail;
  }
  std::size_t samples = 0;
  for (const auto& run : runs) samples += static_cast<std::size_t>(run.size());
  spdlog::info("wrote {} runs ({} samples, sigma = {}, seed = {}) to {}", runs.size(), samples,
               spec->sigma, spec->seed, out_dir.string());
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{
      "hrg-sim: simulate the free runs of a spec (bench_configs/sim-*.toml) and write them "
      "as a session directory (session.json + runs/run-NNN.csv) carrying the truth.\n"
      "Here 1: simulation or writing failed; 4: bad command line, spec, or a non-empty output "
      "directory without --force.\n" +
      std::string(hrgbench::kExitCodesHelp)};
  std::string spec_path;
  std::string out_dir;
  bool force = false;
  bool quiet = false;
  cli.add_option("spec", spec_path, "simulation spec (TOML)")->required();
  cli.add_option("-o,--output", out_dir, "session directory to write")->required();
  cli.add_flag("--force", force, "write into a non-empty directory (replaces an earlier session)");
  hrgbench::app::AddCommonFlags(cli, &quiet);
  return hrgbench::app::ParseAndRun(cli, argc, argv, "hrg-sim", quiet,
                                    [&] { return Run(spec_path, out_dir, force); });
}
