#include "session_document.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <set>

#include "append_file.hpp"
#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::bench::internal {

using nlohmann::json;

std::string RunFileName(int run_id) {
  char name[32];
  std::snprintf(name, sizeof name, "runs/run-%03d.csv", run_id);
  return name;
}

json TimeStampNow() {
  const auto now = std::chrono::system_clock::now();
  const auto us =
      std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count();
  const std::time_t seconds = static_cast<std::time_t>(us / 1'000'000);
  std::tm utc{};
  ::gmtime_r(&seconds, &utc);
  char text[96];  // generous: the compiler cannot bound tm_year
  std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d.%06dZ", utc.tm_year + 1900,
                utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec,
                static_cast<int>(us % 1'000'000));
  return json{{"utc", text}, {"monotonic_ns", MonotonicNs()}};
}

json Number(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }

json ToJson(const PlannedRun& plan) {
  return json{{"commanded_omega_rad_s", plan.commanded_omega_rad_s},
              {"a", plan.a},
              {"b", plan.b},
              {"theta_rad", plan.theta_rad},
              {"free_run_s", plan.free_run_s},
              {"sample_rate_hz", plan.sample_rate_hz}};
}

json ToJson(const RunStart& start) {
  json out{{"commanded_omega_rad_s", Number(start.commanded_omega_rad_s)},
           {"measured_omega_rad_s", Number(start.measured_omega_rad_s)},
           {"earth_rate_rad_s", Number(start.earth_rate_rad_s)},
           {"temperature_c", Number(start.temperature_c)},
           {"resonant_frequency_hz", Number(start.resonant_frequency_hz)},
           {"release_t_ns", start.release_t_ns}};
  out.update(TimeStampNow());
  return out;
}

json ToJson(const RunEnd& end, std::uint64_t samples) {
  json out{{"status", end.status},
           {"reason", end.reason},
           {"omega_rad_s", Number(end.omega_rad_s)},
           {"omega_std_error_rad_s", Number(end.omega_std_error_rad_s)},
           {"omega_readings", end.omega_readings},
           {"omega_source", end.omega_source.empty() ? json(nullptr) : json(end.omega_source)},
           {"omega_rate_rad_s", Number(end.omega_rate_rad_s)},
           {"omega_rate_std_error_rad_s", Number(end.omega_rate_std_error_rad_s)},
           {"omega_rate_readings", end.omega_rate_readings},
           {"omega_angle_rad_s", Number(end.omega_angle_rad_s)},
           {"omega_angle_std_error_rad_s", Number(end.omega_angle_std_error_rad_s)},
           {"omega_angle_readings", end.omega_angle_readings},
           {"temperature_start_c", Number(end.temperature_start_c)},
           {"temperature_end_c", Number(end.temperature_end_c)},
           {"frequency_start_hz", Number(end.frequency_start_hz)},
           {"frequency_end_hz", Number(end.frequency_end_hz)},
           {"sequence_gaps", end.sequence_gaps},
           {"kernel_drops", end.kernel_drops},
           {"bad_frames", end.bad_frames},
           {"reference_phase_undone_samples", end.reference_phase_undone_samples},
           {"reference_phases_missing", end.reference_phases_missing},
           {"samples", samples}};
  if (std::isfinite(end.decided_at_s)) {
    out[session::keys::kDecided] =
        json{{session::keys::kAtS, end.decided_at_s},
             {session::keys::kWhy, end.decided_why},
             {session::keys::kInterimCoverageFactor, Number(end.decided_coverage_factor)}};
  }
  out.update(TimeStampNow());
  return out;
}

json ToJson(const SessionOutcome& outcome) {
  json failed = json::array();
  for (const FailedParameter& p : outcome.failed_parameters) {
    failed.push_back(json{{"name", p.name},
                          {"value", Number(p.value)},
                          {"min", Number(p.min)},
                          {"max", Number(p.max)}});
  }
  json out{{"kind", std::string(ToString(outcome.kind))},
           {"exit_code", ExitCode(outcome.kind)},
           {"reason", outcome.reason},
           {"failed_parameters", std::move(failed)}};
  if (outcome.estimate) out["estimate"] = *outcome.estimate;
  if (outcome.verdict) out["verdict"] = *outcome.verdict;
  if (outcome.ended_early) {
    out[session::keys::kEndedEarly] =
        json{{session::keys::kAfterRun, outcome.ended_early->after_run},
             {session::keys::kPlannedRuns, outcome.ended_early->planned_runs},
             {session::keys::kWhy, outcome.ended_early->why}};
    if (std::isfinite(outcome.ended_early->interim_coverage_factor)) {
      out[session::keys::kEndedEarly][session::keys::kInterimCoverageFactor] =
          outcome.ended_early->interim_coverage_factor;
    }
    if (std::isfinite(outcome.ended_early->within_run_s))
      out[session::keys::kEndedEarly][session::keys::kWithinRunS] =
          outcome.ended_early->within_run_s;
  }
  return out;
}

std::expected<PlannedRun, std::string> PlanFromJson(const json& plan, int run_id) {
  if (!plan.is_object()) return std::unexpected("runs[id " + std::to_string(run_id) + "].plan");
  PlannedRun out;
  out.id = run_id;
  const std::pair<const char*, double*> fields[] = {
      {"commanded_omega_rad_s", &out.commanded_omega_rad_s},
      {"a", &out.a},
      {"b", &out.b},
      {"theta_rad", &out.theta_rad},
      {"free_run_s", &out.free_run_s},
      {"sample_rate_hz", &out.sample_rate_hz}};
  for (const auto& [key, target] : fields) {
    const auto it = plan.find(key);
    if (it == plan.end() || !it->is_number()) {
      return std::unexpected("run " + std::to_string(run_id) + ": plan." + key +
                             " missing or not a number");
    }
    *target = it->get<double>();
  }
  return out;
}

std::string HeaderProblem(const SessionHeader& header) {
  if (header.unit_serial.empty()) return "unit_serial is empty";
  if (header.station_name.empty()) return "station_name is empty";
  if (header.runs.empty()) return "no planned runs";
  std::set<int> ids;
  for (const PlannedRun& run : header.runs) {
    const std::string which = "run " + std::to_string(run.id) + ": ";
    if (run.id < 1) return which + "id must be >= 1";
    if (!ids.insert(run.id).second) return which + "id repeated";
    for (const double v : {run.commanded_omega_rad_s, run.a, run.b, run.theta_rad}) {
      if (!std::isfinite(v)) return which + "non-finite commanded Ω or wave state";
    }
    if (!std::isfinite(run.free_run_s) || !(run.free_run_s > 0.0)) {
      return which + "free_run_s must be finite and > 0";
    }
    if (!std::isfinite(run.sample_rate_hz) || !(run.sample_rate_hz > 0.0)) {
      return which + "sample_rate_hz must be finite and > 0";
    }
  }
  return {};
}

RecordError FromSessionError(const session::SessionError& error) {
  return RecordError{RecordErrorKind::kIo, error.file, error.ToString()};
}

}  // namespace hrgbench::bench::internal
