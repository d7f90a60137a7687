// session.json → the rows of one session. Reads only what the database indexes; everything else
// stays in the folder. Missing optional keys become NULL columns, never errors: sessions written by
// older bench versions (no engineering quantities, no Ω standard error) import too.

#include "hrgbench/results/session_record.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <string_view>

#include "hrgbench/config_file/sha256.hpp"
#include "hrgbench/session/session.hpp"

namespace hrgbench::results {
namespace {

using nlohmann::json;

const json* Child(const json& j, std::string_view key) {
  if (!j.is_object()) return nullptr;
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

const json* Path(const json& j, std::initializer_list<std::string_view> keys) {
  const json* at = &j;
  for (std::string_view key : keys) {
    at = Child(*at, key);
    if (at == nullptr) return nullptr;
  }
  return at;
}

std::string Text(const json* j) {
  return (j != nullptr && j->is_string()) ? j->get<std::string>() : "";
}

std::optional<double> Number(const json* j) {
  if (j == nullptr || !j->is_number()) return std::nullopt;
  const double v = j->get<double>();
  return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

std::optional<double> At(const json* array, std::size_t i) {
  if (array == nullptr || !array->is_array() || i >= array->size()) return std::nullopt;
  return Number(&(*array)[i]);
}

std::int64_t Count(const json* j) {
  return (j != nullptr && j->is_number_integer()) ? j->get<std::int64_t>() : 0;
}

RunRow ReadRun(const json& run) {
  RunRow row;
  row.run_id = static_cast<int>(Count(Child(run, "id")));
  row.status = Text(Child(run, "status"));
  row.commanded_omega_rad_s = Number(Path(run, {"plan", "commanded_omega_rad_s"}));
  row.free_run_s = Number(Path(run, {"plan", "free_run_s"}));
  row.omega_rad_s = Number(Child(run, "omega_rad_s"));
  row.omega_std_error_rad_s = Number(Path(run, {"end", "omega_std_error_rad_s"}));
  row.earth_rate_rad_s = Number(Path(run, {"start", "earth_rate_rad_s"}));
  row.temperature_start_c = Number(Path(run, {"end", "temperature_start_c"}));
  if (!row.temperature_start_c)
    row.temperature_start_c = Number(Path(run, {"start", "temperature_c"}));
  row.temperature_end_c = Number(Path(run, {"end", "temperature_end_c"}));
  row.frequency_start_hz = Number(Path(run, {"end", "frequency_start_hz"}));
  if (!row.frequency_start_hz)
    row.frequency_start_hz = Number(Path(run, {"start", "resonant_frequency_hz"}));
  row.frequency_end_hz = Number(Path(run, {"end", "frequency_end_hz"}));
  if (const json* samples = Path(run, {"end", "samples"}); samples && samples->is_number_integer())
    row.samples = samples->get<std::int64_t>();
  row.drops = Count(Path(run, {"end", "sequence_gaps"})) +
              Count(Path(run, {"end", "kernel_drops"})) + Count(Path(run, {"end", "bad_frames"}));
  return row;
}

void ReadEstimate(const json& estimate, SessionRecord& record) {
  static constexpr std::string_view kDelta[] = {"delta1", "delta2", "delta3",
                                                "delta4", "delta5", "delta6"};
  static constexpr std::string_view kXi[] = {"xi1", "xi2", "xi3", "xi4"};
  const json* delta = Child(estimate, "delta");
  const json* delta_std = Child(estimate, "delta_std");
  for (std::size_t i = 0; i < 6; ++i) {
    if (!At(delta, i)) continue;
    record.parameters.push_back({std::string(kDelta[i]), At(delta, i), At(delta_std, i), ""});
  }
  const json* xi = Child(estimate, "xi");
  const json* xi_std = Child(estimate, "xi_std");
  for (std::size_t i = 0; i < 4; ++i) {
    if (!At(xi, i)) continue;
    record.parameters.push_back({std::string(kXi[i]), At(xi, i), At(xi_std, i), ""});
  }
  if (auto rms = Number(Child(estimate, "residual_rms")))
    record.parameters.push_back({"residual_rms", rms, std::nullopt, ""});
  if (const json* q = Path(estimate, {"engineering", "quantities"}); q && q->is_array()) {
    for (const json& quantity : *q) {
      const std::string name = Text(Child(quantity, "name"));
      if (name.empty()) continue;
      record.parameters.push_back({name, Number(Child(quantity, "value")),
                                   Number(Child(quantity, "std")), Text(Child(quantity, "unit"))});
    }
  }
  if (const json* w = Child(estimate, "warnings"); w && w->is_array()) {
    for (const json& text : *w)
      if (text.is_string()) record.warnings.push_back(text.get<std::string>());
  }
}

}  // namespace

std::expected<SessionRecord, std::string> ReadSessionRecord(const std::filesystem::path& dir) {
  session::ReadOptions options;
  options.load_samples = false;
  auto loaded = session::ReadSession(dir, options);
  if (!loaded) return std::unexpected(loaded.error().ToString());
  json document = std::move(loaded->document);
  const std::string file = (dir / "session.json").string();
  if (Text(Child(document, "state")) != "closed") {
    return std::unexpected(file + ": field 'state': session not closed (state '" +
                           Text(Child(document, "state")) +
                           "'); a session is uploaded once it has an outcome (resume it first)");
  }
  const json* outcome = Child(document, "outcome");
  if (outcome == nullptr || !outcome->is_object() || Text(Child(*outcome, "kind")).empty()) {
    return std::unexpected(file + ": field 'outcome.kind': missing; a closed session has one");
  }
  SessionRecord record;
  record.serial = loaded->serial;
  record.station = Text(Path(document, {"station", "name"}));
  const json* op = Child(document, "operator");
  record.operator_name = op && op->is_object() ? Text(Child(*op, "name")) : Text(op);
  record.software_version = Text(Path(document, {"software", "version"}));
  record.station_sha256 = Text(Path(document, {"config_sha256", "station"}));
  record.sequence_sha256 = Text(Path(document, {"config_sha256", "sequence"}));
  record.limits_sha256 = Text(Path(document, {"config_sha256", "limits"}));
  record.started_utc = Text(Path(document, {"started", "utc"}));
  record.ended_utc = Text(Path(document, {"ended", "utc"}));
  record.outcome = Text(Child(*outcome, "kind"));
  record.reason = Text(Child(*outcome, "reason"));
  record.exit_code = static_cast<int>(Count(Child(*outcome, "exit_code")));
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(dir, ec);
  record.path = (ec ? dir : absolute).lexically_normal().string();
  if (!record.path.empty() && record.path.back() == '/') record.path.pop_back();

  std::string started_ns;
  if (const json* ns = Path(document, {"started", "monotonic_ns"}); ns && ns->is_number())
    started_ns = ns->dump();
  record.id = config_file::Sha256Hex(record.serial + "\n" + record.station + "\n" +
                                     record.started_utc + "\n" + started_ns)
                  .substr(0, 32);

  if (const json* runs = Child(document, "runs"); runs && runs->is_array()) {
    for (const json& run : *runs) {
      if (!run.is_object()) continue;
      record.runs.push_back(ReadRun(run));
      if (record.runs.back().status == "complete") ++record.complete_runs;
    }
  }
  if (const json* estimate = Child(*outcome, "estimate"); estimate && estimate->is_object())
    ReadEstimate(*estimate, record);
  if (const json* limits = Path(*outcome, {"verdict", "limits"}); limits && limits->is_array()) {
    for (const json& limit : *limits) {
      record.limits.push_back({Text(Child(limit, "quantity")), Number(Child(limit, "min")),
                               Number(Child(limit, "max")), Number(Child(limit, "value")),
                               Number(Child(limit, "std")), Text(Child(limit, "status")),
                               Text(Child(limit, "message"))});
    }
  }
  // One row per name: a name the record lists twice (a hand-edited file) keeps its first value,
  // as a reader of the folder would see it first.
  std::set<std::string> seen;
  std::erase_if(record.parameters,
                [&](const ParameterRow& p) { return !seen.insert(p.name).second; });
  document.erase("results");
  record.content_sha256 = config_file::Sha256Hex(document.dump(2) + "\n");
  return record;
}

}  // namespace hrgbench::results
