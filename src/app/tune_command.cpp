#include "app/tune_command.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <iostream>

#include "app/closed_session_report.hpp"
#include "app/station_factory.hpp"
#include "hrgbench/analysis/gyro_units.hpp"
#include "hrgbench/analysis/recorded_estimate.hpp"
#include "hrgbench/bench/sequencer/sequencer.hpp"
#include "hrgbench/bench/tuning/tune_unit.hpp"
#include "hrgbench/bench/tuning/tune_verdict.hpp"
#include "hrgbench/config/site.hpp"
#include "hrgbench/estimator/compensation.hpp"
#include "hrgbench/session/exit_codes.hpp"
#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_record.hpp"

namespace hrgbench::app {
namespace {

// The unit's p from its record: its complete runs estimated again as the bench did at its close
// (bit for bit the recorded estimate: `hrg-bench replay` checks the same).
std::expected<estimator::CompensationSet, std::string> CompensationFromRecord(
    const std::filesystem::path& dir, const session::SessionRecord& record,
    const bench::BenchConfigs& configs) {
  session::ReadOptions read;
  read.min_samples_per_run = bench::MinimumSamples(bench::Method::kMl);
  read.extra_columns = false;
  auto recorded = session::ReadSession(dir, read);
  if (!recorded) return std::unexpected(recorded.error().ToString());
  const bench::RecordedEstimate estimate =
      bench::EstimateRecordedSession(std::move(*recorded), record, configs.limits.fit);
  const estimator::EstimateSummary& summary = estimate.method.summary;
  estimator::CompensationSet p;
  if (!estimator::CompensationFromEstimate(summary, &p))
    return std::unexpected("the estimate gives no compensation: " + summary.message);
  return p;
}

constexpr double kDegPerHour = analysis::kDegPerHourPerRadPerS;

void PrintText(const bench::TuneResult& r, const bench::TuneVerdict& verdict, std::ostream& out) {
  out << "tune " << bench::ToString(verdict.outcome)
      << (verdict.reason.empty() ? "" : ": " + verdict.reason) << '\n';
  for (std::size_t i = 0; i < r.verified.size(); ++i) {
    const bench::VerifiedRate& v = r.verified[i];
    out << "  Ω " << v.omega_rad_s << " rad/s: angle-dependent rate error "
        << v.before_rms_rad_s * kDegPerHour << " °/h before, ";
    // What the free runs' p leaves (the refine holds): the forcers' part, which only the table
    // shows.
    if (i < r.refine.size())
      out << r.refine[i].fit.angle_dependent_rms_rad_s * kDegPerHour
          << " °/h with p from the free runs, ";
    out << v.after_rms_rad_s * kDegPerHour << " °/h after (predicted "
        << v.predicted_rms_rad_s * kDegPerHour << " °/h)" << (v.met ? "" : "  MISSED") << '\n';
  }
  if (r.chi2_dof > 0)
    out << "  after vs predicted: χ² " << r.chi2 << " on " << r.chi2_dof << " (limit "
        << r.chi2_limit << ")" << (r.consistent ? "" : "  INCONSISTENT") << '\n';
  const analysis::ScaleFactorFit& sf = r.scale_factor;
  if (sf.ok) {
    out << "  over the rates: bias " << sf.bias_rad_s * kDegPerHour << " ± "
        << sf.bias_std_rad_s * kDegPerHour << " °/h, scale-factor error "
        << sf.scale_factor_error * 1e6 << " ± " << sf.scale_factor_error_std * 1e6 << " ppm";
    if (sf.asymmetry_known)
      out << ", asymmetry " << sf.asymmetry * 1e6 << " ± " << sf.asymmetry_std * 1e6 << " ppm";
    if (sf.nonlinearity_known) out << ", nonlinearity " << sf.nonlinearity * 1e6 << " ppm";
    out << '\n';
  }
  if (r.stability) {
    const bench::ZeroRateStability& z = *r.stability;
    // IEEE 952: N in °/√h, B in °/h.
    constexpr double kDegPerSqrtHour = analysis::kDegPerSqrtHourPerRadPerSqrtS;
    if (z.arw_known)
      out << "  zero rate: angle random walk " << z.arw_rad_per_sqrt_s * kDegPerSqrtHour
          << " °/√h [" << z.arw_lower * kDegPerSqrtHour << ", " << z.arw_upper * kDegPerSqrtHour
          << "]";
    out << "  bias instability " << (z.bias_instability_reached ? "" : "below ")
        << z.bias_instability_rad_s * kDegPerHour << " °/h ["
        << z.bias_instability_lower * kDegPerHour << ", " << z.bias_instability_upper * kDegPerHour
        << "] at τ " << z.bias_instability_tau_s << " s"
        << (z.bias_instability_reached ? "" : " (no floor within the hold)") << "\n";
  }
  for (const bench::TuneCheck& check : verdict.checks)
    out << "  " << bench::ToString(check.decision.status) << "  " << check.decision.message << '\n';
  out << "  the electronics hold the block " << r.block_at_end << '\n';
}

}  // namespace

int Tune(const TuneOptions& options) {
  const std::filesystem::path& dir = options.dir;
  bench::TunePlan plan;
  plan.rates_rad_s = options.rates_rad_s;
  if (auto problem = bench::TunePlanProblem(plan)) {
    std::cerr << "--rates: " << *problem << '\n';
    return kExitBadInput;
  }
  auto record = session::ReadSessionRecord(dir);
  if (!record) {
    std::cerr << record.error().ToString() << '\n';
    return kExitBadInput;
  }
  if (!record->outcome || record->outcome->kind != bench::OutcomeKind::kPass) {
    std::cerr << dir.string() << ": tunes a unit whose session closed as PASS; this one "
              << (record->outcome
                      ? "closed as " + std::string(bench::ToString(record->outcome->kind))
                      : std::string("is not closed"))
              << '\n';
    return kExitBadInput;
  }
  auto configs = bench::LoadSavedConfigs(dir);
  if (!configs) {
    std::cerr << configs.error() << '\n';
    return kExitBadInput;
  }
  if (bench::FittedPositions(configs->station).size() != 1) {
    std::cerr << dir.string() << ": tune takes one unit's session (a fixture's unit folder)\n";
    return kExitBadInput;
  }
  auto p = CompensationFromRecord(dir, *record, *configs);
  if (!p) {
    std::cerr << dir.string() << ": " << p.error() << '\n';
    return kExitBadInput;
  }
  auto station = OpenStation(configs->station);
  if (!station) {
    spdlog::error("{}", station.error());
    return kExitError;
  }
  plan.verify_turns = options.verify_turns;
  plan.refine_turns = options.refine_turns;
  plan.hold.sample_rate_hz = options.sample_rate_hz;
  plan.zero_rate_hold_s = options.zero_rate_hold_s;
  plan.min_improvement = configs->limits.tune.min_improvement;
  // The table settles as the session's sequence says.
  plan.hold.stable.tolerance_rad_s = configs->sequence.settle.rate_tolerance_rad_s;
  plan.hold.stable.dwell_s = configs->sequence.settle.dwell_s;
  plan.hold.stable.poll_period_s = configs->sequence.settle.poll_period_s;
  plan.hold.settle_timeout_s = configs->sequence.timeouts.settle_s;
  // The tuning checks the program's interrupt count between its reads.
  const bench::BenchHardware& hardware = (*station)->hardware();
  const bench::TuneResult result = bench::TuneUnit(
      hardware, hardware.units.front(), *p, plan, bench::EarthRateOnAxisRadS(configs->station.site),
      options.interrupts, [](std::string_view line) { spdlog::info("{}", line); });
  const bool stopped = options.interrupts != nullptr && options.interrupts->load() > 0;
  const bench::TuneVerdict verdict = bench::JudgeTune(result, configs->limits, stopped);
  nlohmann::json doc = bench::TuneResultJson(result);
  doc["format"] = "hrgbench-tune";
  doc["version"] = 1;
  doc["session"] = dir.filename().string();
  doc["limits"] =
      configs->limits.file.empty() ? nlohmann::json(nullptr) : nlohmann::json(configs->limits.name);
  doc["verdict"] = bench::TuneVerdictJson(verdict);
  if (auto written = session::WriteFileAtomic(dir / "tune.json", doc.dump(2) + "\n"); !written) {
    spdlog::error("{}", written.error().ToString());
    return kExitError;
  }
  if (options.json) {
    std::cout << doc.dump() << '\n';
  } else {
    PrintText(result, verdict, std::cout);
  }
  const std::string html = ReportTunedSession(dir, *configs, options.report);
  if (!options.json && !html.empty()) std::cout << "report: " << html << '\n';
  return bench::ExitCode(verdict.outcome);
}

std::string ReportTunedSession(const std::filesystem::path& dir, const bench::BenchConfigs& configs,
                               ReportMode mode) {
  bench::SessionResult closed;
  closed.dir = dir;
  return MakeReports({closed}, configs.station.results_url, configs.station.report_paper, mode)
      .front()
      .path;
}

}  // namespace hrgbench::app
