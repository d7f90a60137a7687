// The typed session record → the rows of one session. Takes only what the database indexes;
// everything else stays in the folder. Optional fields the record lacks (sessions written by older
// bench versions: no engineering quantities, no Ω standard error) become NULL columns, never
// errors.

#include "hrgbench/results/session_row.hpp"

#include <cmath>
#include <set>
#include <string_view>

#include "hrgbench/config/limits_config.hpp"
#include "hrgbench/config/sequence_config.hpp"
#include "hrgbench/config/sha256.hpp"
#include "hrgbench/results/utc_text.hpp"
#include "hrgbench/session/session_record_keys.hpp"

namespace hrgbench::results {
namespace {

// NaN (not recorded, or null) is a NULL column.
std::optional<double> Value(double v) {
  return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

RunRow ToRunRow(const session::RunRecord& run) {
  RunRow row;
  row.run_id = run.id;
  row.status = run.status;
  if (run.plan) {
    row.commanded_omega_rad_s = Value(run.plan->commanded_omega_rad_s);
    row.free_run_s = Value(run.plan->free_run_s);
  }
  row.omega_rad_s = Value(run.omega_rad_s);
  if (run.start) {
    row.earth_rate_rad_s = Value(run.start->values.earth_rate_rad_s);
    row.temperature_start_c = Value(run.start->values.temperature_c);
    row.frequency_start_hz = Value(run.start->values.resonant_frequency_hz);
  }
  if (run.end) {
    const bench::RunEnd& end = run.end->values;
    row.omega_std_error_rad_s = Value(end.omega_std_error_rad_s);
    // The end's drift fields when recorded; the release conditions otherwise.
    if (const auto t = Value(end.temperature_start_c)) row.temperature_start_c = t;
    row.temperature_end_c = Value(end.temperature_end_c);
    if (const auto f = Value(end.frequency_start_hz)) row.frequency_start_hz = f;
    row.frequency_end_hz = Value(end.frequency_end_hz);
    if (run.end->samples) row.samples = static_cast<std::int64_t>(*run.end->samples);
    row.drops = static_cast<std::int64_t>(end.sequence_gaps + end.kernel_drops + end.bad_frames);
  }
  return row;
}

void AddEstimate(const session::EstimateRecord& estimate, SessionRow& row) {
  static constexpr std::string_view kDelta[] = {"delta1", "delta2", "delta3",
                                                "delta4", "delta5", "delta6"};
  // The model's units (docs/reference/session-json.md): δ1, δ3, δ4 damping rates, δ2 a gain,
  // δ5, δ6 frequency terms. "1" for a dimensionless quantity: an empty unit reads as "unknown".
  static constexpr std::string_view kDeltaUnit[] = {"1/s", "1", "1/s", "1/s", "rad/s", "rad/s"};
  static constexpr std::string_view kXi[] = {"xi1", "xi2", "xi3", "xi4"};
  for (std::size_t i = 0; i < 6; ++i) {
    if (!Value(estimate.delta[i])) continue;
    row.parameters.push_back({std::string(kDelta[i]), Value(estimate.delta[i]),
                              Value(estimate.delta_std[i]), std::string(kDeltaUnit[i])});
  }
  for (std::size_t i = 0; i < 4; ++i) {
    if (!Value(estimate.xi[i])) continue;
    row.parameters.push_back(
        {std::string(kXi[i]), Value(estimate.xi[i]), Value(estimate.xi_std[i]), "1"});
  }
  if (const auto rms = Value(estimate.residual_rms))
    row.parameters.push_back({"residual_rms", rms, std::nullopt, "unit of y"});
  for (const session::EngineeringQuantityRecord& q : estimate.engineering) {
    if (q.name.empty()) continue;
    row.parameters.push_back({q.name, Value(q.value), Value(q.std), q.unit.empty() ? "1" : q.unit});
  }
  row.warnings.insert(row.warnings.end(), estimate.warnings.begin(), estimate.warnings.end());
}

// The names of the configs the session ran with, from the copies the bench saved beside
// session.json (the record holds only their hashes). A copy that is absent (a hand-made record)
// or no longer loads (a key a later program dropped) leaves the name empty: the hash still says
// which file it was.
void AddConfigNames(const std::filesystem::path& dir, SessionRow& row) {
  std::error_code ec;
  const std::filesystem::path sequence = dir / "config" / "sequence.toml";
  if (std::filesystem::is_regular_file(sequence, ec)) {
    if (auto loaded = bench::LoadSequenceConfig(sequence)) row.sequence_name = loaded->name;
  }
  const std::filesystem::path limits = dir / "config" / "limits.toml";
  if (!row.limits_sha256.empty() && std::filesystem::is_regular_file(limits, ec)) {
    if (auto loaded = bench::LoadLimitsConfig(limits)) {
      row.limits_name = loaded->name;
      row.product = loaded->product;
    }
  }
}

}  // namespace

std::expected<SessionRow, std::string> ToSessionRow(const session::SessionRecord& record) {
  const std::string file = record.file.string();
  if (record.state != session::keys::kStateClosed) {
    return std::unexpected(file + ": field 'state': session not closed (state '" + record.state +
                           "'); a session is uploaded once it has an outcome (resume it first)");
  }
  if (!record.outcome) {
    return std::unexpected(file + ": field 'outcome.kind': missing; a closed session has one");
  }
  const session::OutcomeRecord& outcome = *record.outcome;
  SessionRow row;
  row.serial = record.unit_serial;
  row.station = record.station_name;
  row.operator_name = record.operator_name;
  row.software_version = record.software_version;
  row.station_sha256 = record.config_sha256.station_sha256;
  row.sequence_sha256 = record.config_sha256.sequence_sha256;
  row.limits_sha256 = record.config_sha256.limits_sha256;
  // The store keeps one text form of a time (utc_text.hpp); the id below keeps the recorded one.
  const std::string recorded_start = record.started ? record.started->utc : "";
  const auto started = CanonicalUtc(recorded_start);
  if (!started) {
    return std::unexpected(file + ": field 'started.utc': '" + recorded_start +
                           "' is not an ISO 8601 time with a zone (2026-11-23T14:05:00.123456Z)");
  }
  row.started_utc = *started;
  if (record.ended && !record.ended->utc.empty()) {
    const auto ended = CanonicalUtc(record.ended->utc);
    if (!ended) {
      return std::unexpected(file + ": field 'ended.utc': '" + record.ended->utc +
                             "' is not an ISO 8601 time with a zone (2026-11-23T14:05:00.123456Z)");
    }
    row.ended_utc = *ended;
  }
  if (record.fixture.is_object()) {
    const auto position = record.fixture.find("position");
    if (position != record.fixture.end() && position->is_string())
      row.fixture_position = position->get<std::string>();
  }
  row.outcome = std::string(bench::ToString(outcome.kind));
  row.reason = outcome.reason;
  row.exit_code = outcome.exit_code.value_or(0);
  const std::filesystem::path dir = record.file.parent_path();
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(dir, ec);
  row.path = (ec ? dir : absolute).lexically_normal().string();
  if (!row.path.empty() && row.path.back() == '/') row.path.pop_back();

  std::string started_ns;
  if (record.started && record.started->monotonic_ns)
    started_ns = std::to_string(*record.started->monotonic_ns);
  row.id = config_file::Sha256Hex(row.serial + "\n" + row.station + "\n" + recorded_start + "\n" +
                                  started_ns)
               .substr(0, 32);
  AddConfigNames(dir, row);

  for (const session::RunRecord& run : record.runs) {
    row.runs.push_back(ToRunRow(run));
    if (run.status == bench::kRunComplete) ++row.complete_runs;
  }
  if (outcome.estimate) AddEstimate(*outcome.estimate, row);
  if (outcome.verdict) {
    for (const session::LimitRowRecord& limit : outcome.verdict->limits) {
      row.limits.push_back({limit.quantity, Value(limit.min), Value(limit.max), Value(limit.value),
                            Value(limit.std), limit.status, limit.message});
    }
  }
  // One row per name: a name the record lists twice (a hand-edited file) keeps its first value,
  // as a reader of the folder would see it first.
  std::set<std::string> seen;
  std::erase_if(row.parameters, [&](const ParameterRow& p) { return !seen.insert(p.name).second; });
  // The content as the bench closed it: without the upload mark (session_row.hpp).
  nlohmann::json document = record.document;
  document.erase(session::keys::kResults);
  row.content_sha256 = config_file::Sha256Hex(document.dump(2) + "\n");
  return row;
}

std::expected<SessionRow, std::string> ReadSessionRow(const std::filesystem::path& dir) {
  auto record = session::ReadSessionRecord(dir);
  if (!record) return std::unexpected(record.error().ToString());
  return ToSessionRow(*record);
}

}  // namespace hrgbench::results
