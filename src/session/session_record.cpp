// session.json → SessionRecord: the one reader of the record. ReadSession's checks run first (the
// bounds, format, version, the run list); this file types the rest. A key that older benches did
// not write is absent, never an error; a key that is there with the wrong type is the one error.

#include "hrgbench/session/session_record.hpp"

#include <climits>
#include <cmath>
#include <string_view>
#include <system_error>
#include <utility>

#include "hrgbench/estimator/noise_shape.hpp"
#include "hrgbench/session/session_record_keys.hpp"
#include "json_lines.hpp"
#include "session_text.hpp"
#include "whole_file.hpp"

namespace hrgbench::session {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::size_t kMaxShown = 60;

std::string Describe(const json& value) {
  if (value.is_null()) return "null";
  std::string text = value.dump();
  if (text.size() > kMaxShown) text = text.substr(0, kMaxShown) + "...";
  return std::string(value.type_name()) + " " + text;
}

std::string Join(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

std::string Index(const std::string& parent, std::size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

// Typed access with a sticky first error: every getter after a failure does nothing, so the code
// below reads as a list of fields and the first damaged one is the one named.
class Fields {
 public:
  Fields(const std::string* text, fs::path file) : text_(text), file_(std::move(file)) {}

  bool ok() const { return !error_.has_value(); }
  std::optional<SessionError> TakeError() { return std::move(error_); }

  void Fail(const std::string& path, const std::string& message) {
    if (error_) return;
    const std::size_t line = text_ != nullptr ? internal::JsonValueLine(*text_, path) : 0;
    error_ = SessionError{file_, line, path, message};
  }

  // The member, or nullptr when absent or null.
  const json* Find(const json& object, std::string_view key) const {
    if (!object.is_object()) return nullptr;
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) return nullptr;
    return &*it;
  }

  const json* Object(const json& parent, const std::string& path, std::string_view key) {
    const json* value = Find(parent, key);
    if (value == nullptr || !ok()) return nullptr;
    if (!value->is_object()) {
      Fail(Join(path, key), "expected an object, got " + Describe(*value));
      return nullptr;
    }
    return value;
  }

  const json* Array(const json& parent, const std::string& path, std::string_view key) {
    const json* value = Find(parent, key);
    if (value == nullptr || !ok()) return nullptr;
    if (!value->is_array()) {
      Fail(Join(path, key), "expected an array, got " + Describe(*value));
      return nullptr;
    }
    return value;
  }

  // Absent or null: "".
  std::string String(const json& parent, const std::string& path, std::string_view key) {
    const json* value = Find(parent, key);
    if (value == nullptr || !ok()) return {};
    if (!value->is_string()) {
      Fail(Join(path, key), "expected a string, got " + Describe(*value));
      return {};
    }
    return value->get<std::string>();
  }

  // Absent or null: NaN (the writer's "not measured").
  double Number(const json& value, const std::string& path) {
    if (value.is_null() || !ok()) return kNotRecorded;
    if (!value.is_number()) {
      Fail(path, "expected a number or null, got " + Describe(value));
      return kNotRecorded;
    }
    return value.get<double>();
  }
  double Number(const json& parent, const std::string& path, std::string_view key) {
    const json* value = Find(parent, key);
    return value == nullptr ? kNotRecorded : Number(*value, Join(path, key));
  }

  // A count (>= 0). Absent or null: 0.
  std::uint64_t Count(const json& parent, const std::string& path, std::string_view key) {
    const json* value = Find(parent, key);
    if (value == nullptr || !ok()) return 0;
    if (!value->is_number_integer() ||
        (!value->is_number_unsigned() && value->get<std::int64_t>() < 0)) {
      Fail(Join(path, key), "expected an integer >= 0, got " + Describe(*value));
      return 0;
    }
    return value->get<std::uint64_t>();
  }

  std::optional<std::int64_t> Int64(const json& parent, const std::string& path,
                                    std::string_view key) {
    const json* value = Find(parent, key);
    if (value == nullptr || !ok()) return std::nullopt;
    if (!value->is_number_integer() ||
        (value->is_number_unsigned() && value->get<std::uint64_t>() > INT64_MAX)) {
      Fail(Join(path, key), "expected an integer, got " + Describe(*value));
      return std::nullopt;
    }
    return value->get<std::int64_t>();
  }

  std::optional<int> Int(const json& parent, const std::string& path, std::string_view key) {
    const auto wide = Int64(parent, path, key);
    if (!wide) return std::nullopt;
    if (*wide < INT_MIN || *wide > INT_MAX) {
      Fail(Join(path, key), "integer out of range: " + std::to_string(*wide));
      return std::nullopt;
    }
    return static_cast<int>(*wide);
  }

  std::optional<bool> Bool(const json& parent, const std::string& path, std::string_view key) {
    const json* value = Find(parent, key);
    if (value == nullptr || !ok()) return std::nullopt;
    if (!value->is_boolean()) {
      Fail(Join(path, key), "expected true or false, got " + Describe(*value));
      return std::nullopt;
    }
    return value->get<bool>();
  }

  // A fixed-size array of numbers or nulls; absent: all NaN. Shorter arrays leave NaN at the end
  // (a method that reports fewer components), longer ones are an error.
  template <std::size_t N>
  std::array<double, N> Numbers(const json& parent, const std::string& path, std::string_view key) {
    std::array<double, N> out;
    out.fill(kNotRecorded);
    const json* array = Array(parent, path, key);
    if (array == nullptr) return out;
    if (array->size() > N) {
      Fail(Join(path, key), "expected at most " + std::to_string(N) + " numbers, got " +
                                std::to_string(array->size()));
      return out;
    }
    for (std::size_t i = 0; i < array->size(); ++i)
      out[i] = Number((*array)[i], Index(Join(path, key), i));
    return out;
  }

  std::vector<std::string> Strings(const json& parent, const std::string& path,
                                   std::string_view key) {
    std::vector<std::string> out;
    const json* array = Array(parent, path, key);
    if (array == nullptr) return out;
    for (std::size_t i = 0; i < array->size(); ++i) {
      if (!(*array)[i].is_string()) {
        Fail(Index(Join(path, key), i), "expected a string, got " + Describe((*array)[i]));
        return out;
      }
      out.push_back((*array)[i].get<std::string>());
    }
    return out;
  }

 private:
  const std::string* text_;  // for line numbers; nullptr when reading a document
  fs::path file_;
  std::optional<SessionError> error_;
};

std::optional<TimeStampRecord> ReadTimeStamp(Fields& f, const json& parent, const std::string& path,
                                             std::string_view key) {
  const json* object = f.Object(parent, path, key);
  if (object == nullptr) return std::nullopt;
  const std::string at = Join(path, key);
  return TimeStampRecord{f.String(*object, at, keys::kUtc),
                         f.Int64(*object, at, keys::kMonotonicNs)};
}

std::optional<bench::PlannedRun> ReadPlan(Fields& f, const json& run, const std::string& path,
                                          int id) {
  const json* plan = f.Object(run, path, keys::kPlan);
  if (plan == nullptr) return std::nullopt;
  const std::string at = Join(path, keys::kPlan);
  bench::PlannedRun out;
  out.id = id;
  const std::pair<const char*, double*> fields[] = {
      {"commanded_omega_rad_s", &out.commanded_omega_rad_s},
      {"a", &out.a},
      {"b", &out.b},
      {"theta_rad", &out.theta_rad},
      {"free_run_s", &out.free_run_s},
      {"sample_rate_hz", &out.sample_rate_hz}};
  // The recorder writes every field; a hand-made record (a results-store fixture) may hold only
  // some: absent is NaN, and a reader that needs the whole plan (resume, replay) checks it.
  for (const auto& [key, target] : fields) *target = f.Number(*plan, at, key);
  return out;
}

std::optional<RunStartRecord> ReadStart(Fields& f, const json& parent, const std::string& path) {
  const json* start = f.Object(parent, path, keys::kStart);
  if (start == nullptr) return std::nullopt;
  const std::string at = Join(path, keys::kStart);
  RunStartRecord out;
  bench::RunStart& v = out.values;
  v.commanded_omega_rad_s = f.Number(*start, at, "commanded_omega_rad_s");
  v.measured_omega_rad_s = f.Number(*start, at, "measured_omega_rad_s");
  v.earth_rate_rad_s = f.Number(*start, at, "earth_rate_rad_s");
  v.temperature_c = f.Number(*start, at, "temperature_c");
  v.resonant_frequency_hz = f.Number(*start, at, "resonant_frequency_hz");
  v.release_t_ns = f.Int64(*start, at, "release_t_ns").value_or(0);
  out.at = {f.String(*start, at, keys::kUtc), f.Int64(*start, at, keys::kMonotonicNs)};
  return out;
}

std::optional<RunEndRecord> ReadEnd(Fields& f, const json& parent, const std::string& path) {
  const json* end = f.Object(parent, path, keys::kEnd);
  if (end == nullptr) return std::nullopt;
  const std::string at = Join(path, keys::kEnd);
  RunEndRecord out;
  bench::RunEnd& v = out.values;
  v.status = f.String(*end, at, keys::kStatus);
  v.reason = f.String(*end, at, keys::kReason);
  v.omega_rad_s = f.Number(*end, at, "omega_rad_s");
  v.omega_std_error_rad_s = f.Number(*end, at, "omega_std_error_rad_s");
  v.omega_readings = f.Count(*end, at, "omega_readings");
  v.omega_source = f.String(*end, at, "omega_source");
  v.omega_rate_rad_s = f.Number(*end, at, "omega_rate_rad_s");
  v.omega_rate_std_error_rad_s = f.Number(*end, at, "omega_rate_std_error_rad_s");
  v.omega_rate_readings = f.Count(*end, at, "omega_rate_readings");
  v.omega_angle_rad_s = f.Number(*end, at, "omega_angle_rad_s");
  v.omega_angle_std_error_rad_s = f.Number(*end, at, "omega_angle_std_error_rad_s");
  v.omega_angle_readings = f.Count(*end, at, "omega_angle_readings");
  v.temperature_start_c = f.Number(*end, at, "temperature_start_c");
  v.temperature_end_c = f.Number(*end, at, "temperature_end_c");
  v.frequency_start_hz = f.Number(*end, at, "frequency_start_hz");
  v.frequency_end_hz = f.Number(*end, at, "frequency_end_hz");
  v.sequence_gaps = f.Count(*end, at, "sequence_gaps");
  v.kernel_drops = f.Count(*end, at, "kernel_drops");
  v.bad_frames = f.Count(*end, at, "bad_frames");
  v.reference_phase_undone_samples = f.Count(*end, at, "reference_phase_undone_samples");
  v.reference_phases_missing = f.Count(*end, at, "reference_phases_missing");
  if (f.Find(*end, keys::kSamples) != nullptr) out.samples = f.Count(*end, at, keys::kSamples);
  if (const json* decided = f.Object(*end, at, keys::kDecided)) {
    const std::string d = Join(at, keys::kDecided);
    v.decided_at_s = f.Number(*decided, d, keys::kAtS);
    v.decided_why = f.String(*decided, d, keys::kWhy);
    v.decided_coverage_factor = f.Number(*decided, d, keys::kInterimCoverageFactor);
  }
  out.at = {f.String(*end, at, keys::kUtc), f.Int64(*end, at, keys::kMonotonicNs)};
  return out;
}

void ReadRunDetails(Fields& f, const json& run, const std::string& path, RunRecord& out) {
  out.plan = ReadPlan(f, run, path, out.id);
  out.start = ReadStart(f, run, path);
  out.end = ReadEnd(f, run, path);
  const json* attempts = f.Array(run, path, keys::kAttempts);
  if (attempts == nullptr) return;
  for (std::size_t k = 0; k < attempts->size() && f.ok(); ++k) {
    const std::string at = Index(Join(path, keys::kAttempts), k);
    const json& item = (*attempts)[k];
    if (!item.is_object()) {
      f.Fail(at, "expected an object, got " + Describe(item));
      return;
    }
    AttemptRecord attempt;
    attempt.status = f.String(item, at, keys::kStatus);
    attempt.file = f.String(item, at, keys::kFile);
    attempt.start = ReadStart(f, item, at);
    attempt.end = ReadEnd(f, item, at);
    out.attempts.push_back(std::move(attempt));
  }
}

// prompts (absent: none). A string field that is null (no image, nobody answered) reads as "".
std::vector<PromptRecord> ReadPrompts(Fields& f, const json& doc) {
  std::vector<PromptRecord> out;
  const json* prompts = f.Array(doc, "", keys::kPrompts);
  if (prompts == nullptr) return out;
  for (std::size_t k = 0; k < prompts->size() && f.ok(); ++k) {
    const std::string at = Index(keys::kPrompts, k);
    const json& item = (*prompts)[k];
    if (!item.is_object()) {
      f.Fail(at, "expected an object, got " + Describe(item));
      return out;
    }
    PromptRecord prompt;
    prompt.id = f.String(item, at, keys::kId);
    prompt.at = f.String(item, at, keys::kAt);
    prompt.text = f.String(item, at, keys::kText);
    prompt.image_sha256 = f.String(item, at, keys::kImageSha256);
    prompt.shown = ReadTimeStamp(f, item, at, keys::kShown);
    prompt.answered = ReadTimeStamp(f, item, at, keys::kAnswered);
    prompt.answer = f.String(item, at, keys::kAnswer);
    if (!prompt.answer.empty() && prompt.answer != bench::kPromptConfirmed &&
        prompt.answer != bench::kPromptAborted && prompt.answer != bench::kPromptInterrupted) {
      f.Fail(
          Join(at, keys::kAnswer),
          "expected \"confirmed\", \"aborted\" or \"interrupted\", got \"" + prompt.answer + "\"");
      return out;
    }
    prompt.by = f.String(item, at, keys::kBy);
    prompt.how = f.String(item, at, keys::kHow);
    prompt.reason = f.String(item, at, keys::kReason);
    out.push_back(std::move(prompt));
  }
  return out;
}

// engineering.quantities[k].budget (absent: empty).
std::vector<UncertaintyComponentRecord> ReadBudget(Fields& f, const json& quantity,
                                                   const std::string& at) {
  std::vector<UncertaintyComponentRecord> out;
  const json* budget = f.Array(quantity, at, keys::kBudget);
  if (budget == nullptr) return out;
  for (std::size_t c = 0; c < budget->size() && f.ok(); ++c) {
    const std::string b = Index(Join(at, keys::kBudget), c);
    const json& item = (*budget)[c];
    if (!item.is_object()) {
      f.Fail(b, "expected an object, got " + Describe(item));
      break;
    }
    out.push_back({f.String(item, b, keys::kSource), f.String(item, b, keys::kType),
                   f.Number(item, b, keys::kStandardUncertainty), f.String(item, b, keys::kNote)});
  }
  return out;
}

// fit.runs (absent: empty).
std::vector<FitRunRecord> ReadFitRuns(Fields& f, const json& fit, const std::string& at) {
  std::vector<FitRunRecord> out;
  const json* runs = f.Array(fit, at, keys::kRuns);
  if (runs == nullptr) return out;
  for (std::size_t k = 0; k < runs->size() && f.ok(); ++k) {
    const std::string r = Index(Join(at, keys::kRuns), k);
    const json& item = (*runs)[k];
    if (!item.is_object()) {
      f.Fail(r, "expected an object, got " + Describe(item));
      break;
    }
    FitRunRecord run;
    run.run = f.Int(item, r, keys::kRun).value_or(0);
    run.residual_rms = f.Number(item, r, keys::kResidualRms);
    run.noise_sigma = f.Number(item, r, keys::kNoiseSigma);
    run.residual_ratio = f.Number(item, r, keys::kResidualRatio);
    run.whiteness_z = f.Number(item, r, keys::kWhitenessZ);
    run.outliers_removed = f.Number(item, r, keys::kOutliersRemoved);
    run.omega_offset_in_std = f.Number(item, r, keys::kOmegaOffsetInStd);
    out.push_back(run);
  }
  return out;
}

EstimateRecord ReadEstimate(Fields& f, const json& estimate, const std::string& at) {
  EstimateRecord out;
  out.method = f.String(estimate, at, "method");
  out.termination = f.String(estimate, at, "termination");
  out.iterations = f.Int(estimate, at, "iterations").value_or(0);
  out.samples_used = f.Int64(estimate, at, "samples_used").value_or(0);
  out.delta = f.Numbers<6>(estimate, at, "delta");
  out.delta_std = f.Numbers<6>(estimate, at, "delta_std");
  out.xi = f.Numbers<4>(estimate, at, "xi");
  out.xi_std = f.Numbers<4>(estimate, at, "xi_std");
  out.residual_rms = f.Number(estimate, at, "residual_rms");
  out.noise_sigma = f.Number(estimate, at, "noise_sigma");
  out.warnings = f.Strings(estimate, at, "warnings");
  out.delta_recorded = f.Find(estimate, keys::kDelta) != nullptr;
  if (const json* engineering = f.Object(estimate, at, "engineering")) {
    const std::string e = Join(at, "engineering");
    out.engineering_recorded = true;
    out.engineering_frequency_hz = f.Number(*engineering, e, "frequency_hz");
    out.engineering_frequency_source = f.String(*engineering, e, keys::kFrequencySource);
    out.engineering_coverage_factor = f.Number(*engineering, e, keys::kCoverageFactor);
    out.engineering_limitations = f.Strings(*engineering, e, keys::kLimitations);
    if (const json* quantities = f.Array(*engineering, e, "quantities")) {
      for (std::size_t k = 0; k < quantities->size() && f.ok(); ++k) {
        const std::string q = Index(Join(e, "quantities"), k);
        const json& item = (*quantities)[k];
        if (!item.is_object()) {
          f.Fail(q, "expected an object, got " + Describe(item));
          break;
        }
        EngineeringQuantityRecord row;
        row.name = f.String(item, q, "name");
        row.label = f.String(item, q, "label");
        row.unit = f.String(item, q, "unit");
        row.value = f.Number(item, q, "value");
        row.std = f.Number(item, q, "std");
        row.determined = f.Bool(item, q, "determined").value_or(false);
        row.note = f.String(item, q, "note");
        row.budget = ReadBudget(f, item, q);
        out.engineering.push_back(std::move(row));
      }
    }
  }
  if (const json* fit = f.Object(estimate, at, "fit")) {
    out.phase_degree = f.Int(*fit, Join(at, "fit"), "phase_degree").value_or(0);
    out.covariance_kind = f.String(*fit, Join(at, keys::kFit), keys::kCovariance);
    if (const json* limits = f.Object(*fit, Join(at, "fit"), "limits")) {
      const std::string l = Join(at, "fit.limits");
      out.fit_residual_ratio_max = f.Number(*limits, l, "residual_ratio_max");
      out.fit_whiteness_z_max = f.Number(*limits, l, "whiteness_z_max");
      out.fit_omega_offset_max_in_std = f.Number(*limits, l, "omega_offset_max_in_std");
    }
    out.fit_runs = ReadFitRuns(f, *fit, Join(at, keys::kFit));
  }
  if (const json* fitted = f.Array(estimate, at, keys::kFittedRuns)) {
    out.fitted_runs_recorded = true;
    for (std::size_t k = 0; k < fitted->size() && f.ok(); ++k) {
      const std::string r = Index(Join(at, keys::kFittedRuns), k);
      const json& item = (*fitted)[k];
      if (!item.is_object()) {
        f.Fail(r, "expected an object, got " + Describe(item));
        break;
      }
      FittedRunRecord run;
      run.run_id = f.Int(item, r, "run").value_or(0);
      run.initial_state = f.Numbers<4>(item, r, "initial_state");
      if (const json* q = f.Array(item, r, "phase_coefficients")) {
        for (std::size_t j = 0; j < q->size(); ++j)
          run.phase_coefficients.push_back(
              f.Number((*q)[j], Index(Join(r, "phase_coefficients"), j)));
      }
      const double offset = f.Number(item, r, "omega_offset_rad_s");
      run.omega_offset_rad_s = std::isfinite(offset) ? offset : 0.0;
      out.fitted_runs.push_back(std::move(run));
    }
  }
  if (const json* truth = f.Object(estimate, at, "truth")) {
    const std::string t = Join(at, "truth");
    if (f.Find(*truth, "delta") != nullptr) out.truth_delta = f.Numbers<6>(*truth, t, "delta");
    if (f.Find(*truth, "xi") != nullptr) out.truth_xi = f.Numbers<4>(*truth, t, "xi");
  }
  return out;
}

VerdictRecord ReadVerdict(Fields& f, const json& verdict, const std::string& at) {
  VerdictRecord out;
  out.overall = f.String(verdict, at, "overall");
  out.fit_acceptable = f.Bool(verdict, at, "fit_acceptable");
  if (const json* checks = f.Array(verdict, at, "fit_checks")) {
    for (std::size_t k = 0; k < checks->size() && f.ok(); ++k) {
      const std::string c = Index(Join(at, "fit_checks"), k);
      const json& item = (*checks)[k];
      if (!item.is_object()) {
        f.Fail(c, "expected an object, got " + Describe(item));
        break;
      }
      out.fit_checks.push_back({f.Int(item, c, "run").value_or(0), f.String(item, c, "name"),
                                f.String(item, c, "status"), f.Number(item, c, "value"),
                                f.Number(item, c, "max"), f.String(item, c, "message")});
    }
  }
  if (const json* limits = f.Array(verdict, at, keys::kLimits)) {
    for (std::size_t k = 0; k < limits->size() && f.ok(); ++k) {
      const std::string l = Index(Join(at, keys::kLimits), k);
      const json& item = (*limits)[k];
      if (!item.is_object()) {
        f.Fail(l, "expected an object, got " + Describe(item));
        break;
      }
      LimitRowRecord row;
      row.quantity = f.String(item, l, "quantity");
      row.status = f.String(item, l, "status");
      row.value = f.Number(item, l, "value");
      row.std = f.Number(item, l, "std");
      row.min = f.Number(item, l, "min");
      row.max = f.Number(item, l, "max");
      row.message = f.String(item, l, "message");
      row.rule = f.String(item, l, keys::kRule);
      row.zone = f.String(item, l, keys::kZone);
      row.coverage_factor = f.Number(item, l, keys::kCoverageFactor);
      row.expanded_uncertainty = f.Number(item, l, keys::kExpandedUncertainty);
      row.interval_min = f.Number(item, l, keys::kIntervalMin);
      row.interval_max = f.Number(item, l, keys::kIntervalMax);
      row.acceptance_min = f.Number(item, l, keys::kAcceptanceMin);
      row.acceptance_max = f.Number(item, l, keys::kAcceptanceMax);
      row.retest = f.Bool(item, l, keys::kRetest);
      out.limits.push_back(std::move(row));
    }
  }
  if (const json* decision = f.Object(verdict, at, keys::kDecision)) {
    const std::string d = Join(at, keys::kDecision);
    out.decision_rule = f.String(*decision, d, keys::kRule);
    out.decision_coverage_factor = f.Number(*decision, d, keys::kCoverageFactor);
    out.decision_max_uncertainty_ratio = f.Number(*decision, d, keys::kMaxUncertaintyRatio);
  }
  out.retest = f.Bool(verdict, at, keys::kRetest);
  return out;
}

std::optional<OutcomeRecord> ReadOutcome(Fields& f, const json& doc) {
  const json* outcome = f.Object(doc, "", keys::kOutcome);
  if (outcome == nullptr) return std::nullopt;
  const std::string at = keys::kOutcome;
  OutcomeRecord out;
  const std::string kind = f.String(*outcome, at, keys::kKind);
  if (!f.ok()) return std::nullopt;
  const std::optional<bench::OutcomeKind> parsed = bench::ParseOutcomeKind(kind);
  if (parsed) out.kind = *parsed;
  if (!parsed) {
    f.Fail(Join(at, keys::kKind),
           "expected \"PASS\", \"FAIL\", \"ERROR\" or \"ABORTED\", got " +
               (f.Find(*outcome, keys::kKind) != nullptr ? Describe(outcome->at(keys::kKind))
                                                         : std::string("nothing")));
    return std::nullopt;
  }
  out.exit_code = f.Int(*outcome, at, keys::kExitCode);
  out.reason = f.String(*outcome, at, keys::kReason);
  if (const json* failed = f.Array(*outcome, at, keys::kFailedParameters)) {
    for (std::size_t k = 0; k < failed->size() && f.ok(); ++k) {
      const std::string p = Index(Join(at, keys::kFailedParameters), k);
      const json& item = (*failed)[k];
      if (!item.is_object()) {
        f.Fail(p, "expected an object, got " + Describe(item));
        break;
      }
      bench::FailedParameter parameter;
      parameter.name = f.String(item, p, "name");
      parameter.value = f.Number(item, p, "value");
      // null bounds are "no bound" (the writer's non-finite).
      const double min = f.Number(item, p, "min");
      const double max = f.Number(item, p, "max");
      if (std::isfinite(min)) parameter.min = min;
      if (std::isfinite(max)) parameter.max = max;
      out.failed_parameters.push_back(std::move(parameter));
    }
  }
  if (const json* estimate = f.Object(*outcome, at, keys::kEstimate)) {
    out.estimate = ReadEstimate(f, *estimate, Join(at, keys::kEstimate));
    out.estimate_json = *estimate;
  }
  if (const json* verdict = f.Object(*outcome, at, keys::kVerdict)) {
    out.verdict = ReadVerdict(f, *verdict, Join(at, keys::kVerdict));
    out.verdict_json = *verdict;
  }
  if (const json* early = f.Object(*outcome, at, keys::kEndedEarly)) {
    const std::string e = Join(at, keys::kEndedEarly);
    bench::EarlyEnd end;
    end.after_run = f.Int(*early, e, keys::kAfterRun).value_or(0);
    end.planned_runs = f.Int(*early, e, keys::kPlannedRuns).value_or(0);
    end.why = f.String(*early, e, keys::kWhy);
    end.interim_coverage_factor = f.Number(*early, e, keys::kInterimCoverageFactor);
    end.within_run_s = f.Number(*early, e, keys::kWithinRunS);
    out.ended_early = std::move(end);
  }
  return out;
}

// electronics.output_filter (the station's [gyro] output_filter, order, cutoff_hz).
std::optional<bench::OutputFilter> ReadOutputFilter(Fields& f, const json& electronics,
                                                    const std::string& path) {
  const json* filter = f.Find(electronics, keys::kOutputFilter);
  if (filter == nullptr || !f.ok()) return std::nullopt;
  const std::string at = Join(path, keys::kOutputFilter);
  const auto shown = [&](std::string_view key) {
    const json* value = f.Find(*filter, key);
    return value == nullptr ? std::string("nothing") : Describe(*value);
  };
  if (!filter->is_object()) {
    f.Fail(at, "expected an object, got " + Describe(*filter));
    return std::nullopt;
  }
  const json* kind = f.Find(*filter, keys::kKind);
  if (kind == nullptr || !kind->is_string()) {
    f.Fail(Join(at, keys::kKind), "missing or not a string, got " + shown(keys::kKind));
    return std::nullopt;
  }
  if (*kind == keys::kFilterNone) return bench::OutputFilter{};
  if (*kind != keys::kFilterButterworth) {
    f.Fail(Join(at, keys::kKind), "'" + kind->get<std::string>() + "' is not none or butterworth");
    return std::nullopt;
  }
  bench::OutputFilter declared;
  declared.kind = bench::OutputFilterKind::kButterworth;
  const json* order = f.Find(*filter, keys::kOrder);
  if (order == nullptr || !order->is_number_integer() || *order < 1 ||
      *order > estimator::kMaxButterworthOrder) {
    f.Fail(Join(at, keys::kOrder), "missing or not an integer 1 ... " +
                                       std::to_string(estimator::kMaxButterworthOrder) + ", got " +
                                       shown(keys::kOrder));
    return std::nullopt;
  }
  declared.order = order->get<std::int64_t>();
  const json* cutoff = f.Find(*filter, keys::kCutoffHz);
  if (cutoff == nullptr || !cutoff->is_number() || !(cutoff->get<double>() > 0.0) ||
      !std::isfinite(cutoff->get<double>())) {
    f.Fail(Join(at, keys::kCutoffHz),
           "missing or not a positive number, got " + shown(keys::kCutoffHz));
    return std::nullopt;
  }
  declared.cutoff_hz = cutoff->get<double>();
  return declared;
}

// The stage's names as estimator::ToString(CrossTalkStage) writes them, spelled here because this
// library uses the estimator's headers, not its library (the pick-off tests round-trip each one).
std::optional<estimator::CrossTalkStage> ParseStage(const std::string& text) {
  constexpr std::pair<const char*, estimator::CrossTalkStage> kStages[] = {
      {"midway", estimator::CrossTalkStage::kMidway},
      {"before_gain", estimator::CrossTalkStage::kBeforeGain},
      {"after_gain", estimator::CrossTalkStage::kAfterGain}};
  for (const auto& [name, stage] : kStages)
    if (text == name) return stage;
  return std::nullopt;
}

// electronics.pickoff (the station's [gyro] pickoff_cross_talk_stage, pickoff_coupling_bound_rad).
std::optional<bench::PickoffDeclaration> ReadPickoff(Fields& f, const json& electronics,
                                                     const std::string& path) {
  const json* pickoff = f.Find(electronics, keys::kPickoff);
  if (pickoff == nullptr || !f.ok()) return std::nullopt;
  const std::string at = Join(path, keys::kPickoff);
  if (!pickoff->is_object()) {
    f.Fail(at, "expected an object, got " + pickoff->dump());
    return std::nullopt;
  }
  bench::PickoffDeclaration declared;
  if (const json* stage = f.Find(*pickoff, keys::kCrossTalkStage)) {
    const auto parsed = stage->is_string() ? ParseStage(stage->get<std::string>()) : std::nullopt;
    if (!parsed) {
      f.Fail(Join(at, keys::kCrossTalkStage),
             "expected \"midway\", \"before_gain\" or \"after_gain\", got " + stage->dump());
      return std::nullopt;
    }
    declared.cross_talk_stage = *parsed;
  }
  if (const json* bound = f.Find(*pickoff, keys::kUnmodelledCouplingBoundRad)) {
    const double value = bound->is_number() ? bound->get<double>() : kNotRecorded;
    if (!(std::isfinite(value) && value >= 0.0 && value <= bench::kMaxCouplingBoundRad)) {
      f.Fail(Join(at, keys::kUnmodelledCouplingBoundRad),
             "expected a number in [0, " + json(bench::kMaxCouplingBoundRad).dump() + "], got " +
                 bound->dump());
      return std::nullopt;
    }
    declared.unmodelled_coupling_bound_rad = value;
  }
  return declared;
}

ElectronicsRecord ReadElectronics(Fields& f, const json& doc, estimator::IqConvention convention) {
  ElectronicsRecord out;
  out.iq_convention = convention;  // ReadSessionJson read and checked it
  const json* electronics = f.Object(doc, "", keys::kElectronics);
  if (electronics == nullptr) return out;
  out.output_filter = ReadOutputFilter(f, *electronics, keys::kElectronics);
  out.pickoff = ReadPickoff(f, *electronics, keys::kElectronics);
  return out;
}

json Member(const json& doc, const char* key) {
  return doc.is_object() && doc.contains(key) ? doc.at(key) : json(nullptr);
}

// Types what ReadSessionJson did not (it checked format, version, serial, rate, convention, runs).
std::expected<SessionRecord, SessionError> Type(Session&& base, const std::string* text,
                                                const fs::path& file) {
  Fields f(text, file);
  const json& doc = base.document;
  SessionRecord record;
  record.file = file;
  record.format = kFormatName;
  record.version = kFormatVersion;
  record.unit_serial = base.serial;
  record.sample_rate_hz = base.sample_rate_hz;
  record.iq_convention = base.iq_convention;
  record.notes = std::move(base.notes);
  record.warnings = std::move(base.warnings);
  record.state = f.String(doc, "", keys::kState);
  // "operator": a name, or {name} (both have been written by hand-made records).
  if (const json* op = f.Find(doc, keys::kOperator); op != nullptr && op->is_object()) {
    record.operator_name = f.String(*op, keys::kOperator, keys::kName);
  } else {
    record.operator_name = f.String(doc, "", keys::kOperator);
  }
  if (const json* station = f.Object(doc, "", keys::kStation))
    record.station_name = f.String(*station, keys::kStation, keys::kName);
  if (const json* software = f.Object(doc, "", keys::kSoftware))
    record.software_version = f.String(*software, keys::kSoftware, keys::kVersion);
  // hrg-sim's provenance (app/sim_session.cpp) is top-level.
  if (record.software_version.empty())
    record.software_version = f.String(doc, "", keys::kSoftwareVersion);
  record.spec_sha256 = f.String(doc, "", keys::kSpecSha256);
  record.description = f.String(doc, "", keys::kDescription);
  if (const json* hashes = f.Object(doc, "", keys::kConfigSha256)) {
    record.config_sha256.recorded = true;
    record.config_sha256.station_sha256 = f.String(*hashes, keys::kConfigSha256, keys::kStation);
    record.config_sha256.sequence_sha256 = f.String(*hashes, keys::kConfigSha256, keys::kSequence);
    record.config_sha256.limits_sha256 = f.String(*hashes, keys::kConfigSha256, keys::kLimits);
  }
  record.started = ReadTimeStamp(f, doc, "", keys::kStarted);
  record.ended = ReadTimeStamp(f, doc, "", keys::kEnded);
  record.realtime_status = f.String(doc, "", keys::kRealtime);
  if (const json* can = f.Object(doc, "", keys::kCanLog)) {
    CanLogRecord log;
    log.file = f.String(*can, keys::kCanLog, keys::kFile);
    log.interface_name = f.String(*can, keys::kCanLog, keys::kInterface);
    log.node = f.Int64(*can, keys::kCanLog, keys::kNode);
    log.protocol = f.Int64(*can, keys::kCanLog, keys::kProtocol);
    record.can_log = std::move(log);
  }
  record.electronics = ReadElectronics(f, doc, base.iq_convention);
  record.simulation = Member(doc, keys::kSimulation);
  // The rest of "simulation" stays opaque (a section that is not an object is not this reader's).
  if (const json* simulation = f.Find(doc, keys::kSimulation);
      simulation != nullptr && simulation->is_object()) {
    if (f.Find(*simulation, keys::kDelta) != nullptr)
      record.simulation_delta = f.Numbers<6>(*simulation, keys::kSimulation, keys::kDelta);
    if (f.Find(*simulation, keys::kXi) != nullptr)
      record.simulation_xi = f.Numbers<4>(*simulation, keys::kSimulation, keys::kXi);
  }
  record.fixture = Member(doc, keys::kFixture);
  if (record.fixture.is_object()) {
    const auto position = record.fixture.find(keys::kFixturePosition);
    if (position != record.fixture.end() && position->is_string())
      record.fixture_position = position->get<std::string>();
  }
  record.results = Member(doc, keys::kResults);

  // ReadSessionJson checked runs is an array of objects parallel to base.runs.
  const json& runs = doc.at(keys::kRuns);
  for (std::size_t i = 0; i < base.runs.size() && f.ok(); ++i) {
    RunRecord run;
    run.id = base.runs[i].id;
    run.file = base.runs[i].file;
    run.omega_rad_s = base.runs[i].omega_rad_s;
    run.status = base.runs[i].status;
    ReadRunDetails(f, runs[i], Index(keys::kRuns, i), run);
    record.runs.push_back(std::move(run));
  }
  record.prompts = ReadPrompts(f, doc);
  record.outcome = ReadOutcome(f, doc);
  if (auto error = f.TakeError()) return std::unexpected(std::move(*error));
  record.document = std::move(base.document);
  return record;
}

}  // namespace

const RunRecord* SessionRecord::Run(int id) const {
  for (const RunRecord& run : runs)
    if (run.id == id) return &run;
  return nullptr;
}

std::expected<SessionRecord, SessionError> ReadSessionRecord(const fs::path& dir) {
  const fs::path json_file = dir / "session.json";
  try {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
      return std::unexpected(
          SessionError{dir, 0, "", "not a directory (a session is a directory)"});
    }
    const auto text = internal::ReadWholeFile(json_file, kMaxSessionJsonBytes);
    if (!text) return std::unexpected(text.error());
    auto base = internal::ReadSessionJson(*text, json_file);
    if (!base) return std::unexpected(base.error());
    return Type(std::move(*base), &*text, json_file);
  } catch (const json::exception& e) {
    // Not expected after the checks; kept so that no exception crosses the API.
    return std::unexpected(SessionError{json_file, 0, "", e.what()});
  }
}

std::expected<SessionRecord, SessionError> ReadSessionRecord(const json& document,
                                                             const fs::path& file) {
  try {
    // Through the text, so that the bounds and checks are ReadSession's own (one set of them).
    const std::string text = document.dump(2);
    if (text.size() > kMaxSessionJsonBytes) {
      return std::unexpected(SessionError{file, 0, "", "file too large"});
    }
    auto base = internal::ReadSessionJson(text, file);
    if (!base) {
      SessionError error = base.error();
      error.line = 0;  // a line of our own dump would mislead
      return std::unexpected(std::move(error));
    }
    return Type(std::move(*base), nullptr, file);
  } catch (const json::exception& e) {
    return std::unexpected(SessionError{file, 0, "", e.what()});
  }
}

}  // namespace hrgbench::session
