#include "hrgbench/analysis/recorded_runs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "hrgbench/estimator/maximum_likelihood.hpp"

namespace hrgbench::bench {

nlohmann::json PreparedRuns::Json() const {
  nlohmann::json runs_json = nlohmann::json::array();
  for (const ReleaseSkip& skip : skipped)
    runs_json.push_back({{"run", skip.run_id},
                         {"samples_skipped", skip.samples},
                         {"first_fitted_t_s", skip.first_fitted_t_s}});
  nlohmann::json notes_json = nlohmann::json::array();
  for (const std::string& note : notes) notes_json.push_back(note);
  return {{"iq_convention", std::string(estimator::IqConventionName(iq_convention))},
          {"release_settling",
           {{"output_filter", OutputFilterName(output_filter)},
            {"fraction", kReleaseSettlingFraction},
            {"settle_s", settle_s},
            {"runs", runs_json}}},
          {"notes", notes_json}};
}

ReleaseSkip SkipReleaseSettling(double settle_s, estimator::RunData* run_to_cut) {
  estimator::RunData& run = *run_to_cut;
  ReleaseSkip skip;
  skip.run_id = run.id;
  const auto first = std::lower_bound(run.t_s.begin(), run.t_s.end(), settle_s);
  std::size_t count = static_cast<std::size_t>(first - run.t_s.begin());
  // A run too short to lose them keeps what the fit needs (its transient is then fitted).
  const auto size = static_cast<std::size_t>(run.size());
  const auto needed = static_cast<std::size_t>(estimator::kMlMinimumSamples);
  if (size < needed + count) count = size > needed ? size - needed : 0;
  if (count > 0) {
    // In place (a copy of the kept columns would be a second copy of the run): the columns move
    // down, then the storage shrinks (conservativeResize keeping the leading columns).
    const auto kept = static_cast<Eigen::Index>(size - count);
    const auto first_kept = static_cast<Eigen::Index>(count);
    for (Eigen::Index k = 0; k < kept; ++k) run.y.col(k) = run.y.col(k + first_kept);
    run.y.conservativeResize(Eigen::NoChange, kept);
    run.t_s.erase(run.t_s.begin(), run.t_s.begin() + static_cast<std::ptrdiff_t>(count));
  }
  skip.samples = count;
  skip.first_fitted_t_s = run.t_s.empty() ? 0.0 : run.t_s.front();
  return skip;
}

std::vector<ReleaseSkip> SkipReleaseSettling(double settle_s,
                                             std::vector<estimator::RunData>* runs) {
  std::vector<ReleaseSkip> skipped;
  for (estimator::RunData& run : *runs) skipped.push_back(SkipReleaseSettling(settle_s, &run));
  return skipped;
}

namespace {

// Everything but the runs and their skips.
PreparedRuns PreparationOf(const session::Session& recorded,
                           const session::ElectronicsRecord& electronics) {
  PreparedRuns out;
  out.output_filter = RecordedOutputFilter(electronics);
  out.iq_convention = recorded.iq_convention;
  out.notes = recorded.notes;
  out.settle_s = ReleaseSettlingS(out.output_filter);
  return out;
}

// The note on the settling skip, once the runs are skipped.
void NoteSettlingSkip(PreparedRuns* prepared) {
  PreparedRuns& out = *prepared;
  if (out.settle_s > 0.0) {
    std::size_t total = 0;
    for (const ReleaseSkip& skip : out.skipped) total += skip.samples;
    char line[256];
    std::snprintf(line, sizeof line,
                  "the first %.4g s after release not fitted (%zu samples over %zu runs): the "
                  "output filter's settling (%s, to %.0e of a step)",
                  out.settle_s, total, out.skipped.size(),
                  OutputFilterName(out.output_filter).c_str(), kReleaseSettlingFraction);
    out.notes.emplace_back(line);
  }
}

PreparedRuns Prepare(const session::Session& recorded, std::vector<estimator::RunData> runs,
                     const session::ElectronicsRecord& electronics) {
  PreparedRuns out = PreparationOf(recorded, electronics);
  out.runs = std::move(runs);
  out.skipped = SkipReleaseSettling(out.settle_s, &out.runs);
  NoteSettlingSkip(&out);
  return out;
}

}  // namespace

std::expected<PreparedRuns, session::SessionError> SpoolRecordedRuns(
    const std::filesystem::path& dir, const session::Session& recorded,
    const session::ElectronicsRecord& electronics, const session::ReadOptions& options,
    session::RunSpool* spool) {
  PreparedRuns out = PreparationOf(recorded, electronics);
  const auto take =
      [&](const session::RunEntry& entry,
          session::RunSamples&& samples) -> std::expected<void, session::SessionError> {
    estimator::RunData run = session::ToRunData(entry, std::move(samples), recorded.iq_convention);
    out.skipped.push_back(SkipReleaseSettling(out.settle_s, &run));
    return spool->Add(std::move(run));
  };
  if (auto read = session::ReadEachRun(dir, recorded, options, take); !read)
    return std::unexpected(read.error());
  NoteSettlingSkip(&out);
  return out;
}

PreparedRuns PrepareRecordedRuns(const session::Session& recorded,
                                 const session::ElectronicsRecord& electronics) {
  return Prepare(recorded, session::ToRunData(recorded), electronics);
}

PreparedRuns PrepareRecordedRuns(session::Session&& recorded,
                                 const session::ElectronicsRecord& electronics) {
  std::vector<estimator::RunData> runs = session::ToRunData(std::move(recorded));
  return Prepare(recorded, std::move(runs), electronics);
}

namespace {

// runs[].plan's 2ab/(a² + b²) by run id, for the runs whose plan has a and b.
std::map<int, double> PlannedQuadrature(const session::SessionRecord& record) {
  std::map<int, double> out;
  for (const session::RunRecord& run : record.runs) {
    if (!run.plan) continue;
    const double a = run.plan->a, b = run.plan->b;
    const double s = a * a + b * b;
    if (s > 0.0 && std::isfinite(s)) out[run.id] = 2.0 * a * b / s;
  }
  return out;
}

}  // namespace

std::optional<std::string> IqConventionContradiction(const session::SessionRecord& record,
                                                     const estimator::EstimateSummary& summary) {
  if (!summary.IsUsable()) return std::nullopt;
  const std::map<int, double> planned = PlannedQuadrature(record);
  std::size_t taking_part = 0;
  std::string contradicting;
  for (std::size_t r = 0; r < summary.run_nuisance.size(); ++r) {
    const auto plan = planned.find(summary.run_nuisance[r].run_id);
    if (plan == planned.end() || !(std::abs(plan->second) >= kQuadratureSignMinimum)) continue;
    ++taking_part;
    const Eigen::Vector4d& x = summary.run_nuisance[r].initial_state;
    const double fitted = 2.0 * (x[0] * x[3] - x[1] * x[2]) / x.squaredNorm();
    if (!(fitted * plan->second < 0.0 && std::abs(fitted) >= 0.5 * std::abs(plan->second)))
      return std::nullopt;
    char item[96];
    std::snprintf(item, sizeof item, "%srun %d: K/S %.3g, planned %.3g",
                  contradicting.empty() ? "" : "; ", summary.run_nuisance[r].run_id, fitted,
                  plan->second);
    contradicting += item;
  }
  if (taking_part == 0) return std::nullopt;
  return "the data's quadrature at release has the opposite sign of the commanded one in every "
         "run that commanded one (" +
         contradicting +
         "): the electronics' I/Q convention is not the declared one (electronics.iq_convention; "
         "the other convention conjugates y, which the fit cannot see otherwise). delta5, "
         "delta6, xi2, xi3 and the frequency axis are then wrong: declare the station's [gyro] "
         "iq_convention";
}

void NameIqConventionContradiction(const session::SessionRecord& record,
                                   estimator::EstimateSummary* summary) {
  if (auto problem = IqConventionContradiction(record, *summary)) {
    summary->diagnostics.problems.push_back(*problem);
    summary->warnings.push_back(*problem);
  }
}

}  // namespace hrgbench::bench
