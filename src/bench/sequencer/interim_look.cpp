#include "bench/sequencer/interim_look.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <expected>
#include <new>
#include <utility>

#include "hrgbench/analysis/estimate_method.hpp"
#include "hrgbench/session/session.hpp"

namespace hrgbench::bench::internal {
namespace {

// The partial run into the session as the reader would have loaded it were it complete: its
// samples, and its entry complete with the Ω so far (the reader skipped it as "running").
void AddPartialRun(const PartialRun& partial, session::Session& session) {
  session::RunSamples samples;
  samples.t_s = partial.t_s;
  samples.y = Eigen::Map<const Eigen::Matrix4Xd>(partial.y.data(), 4,
                                                 static_cast<Eigen::Index>(partial.t_s.size()));
  session.loaded_run_ids.push_back(partial.run_id);
  session.loaded_samples.push_back(std::move(samples));
  for (session::RunEntry& entry : session.runs) {
    if (entry.id != partial.run_id) continue;
    entry.status = kRunComplete;
    entry.omega_rad_s = partial.omega_rad_s;
    entry.omega_std_rad_s = partial.omega_std_rad_s;
  }
  const std::string skipped = "run " + std::to_string(partial.run_id) + " skipped:";
  std::erase_if(session.warnings, [&](const std::string& w) { return w.rfind(skipped, 0) == 0; });
}

}  // namespace

LaneJudgement JudgeLane(const std::filesystem::path& dir, bool plan_cut_short,
                        const LimitsConfig& limits, const PartialRun* partial, int threads) {
  LaneJudgement out;
  session::ReadOptions read;
  read.min_samples_per_run = MinimumSamples(Method::kMl);
  read.extra_columns = false;  // the estimate reads t_s and y only
  read.plan_cut_short = plan_cut_short;
  auto recorded = session::ReadSession(dir, read);
  // The same document typed by the record's one reader (no second read of the file).
  std::expected<session::SessionRecord, session::SessionError> record =
      recorded ? session::ReadSessionRecord(recorded->document, dir / "session.json")
               : std::unexpected(recorded.error());
  if (!record) {
    out.error = "the record cannot be read back: " + record.error().ToString();
    return out;
  }
  if (partial != nullptr && partial->t_s.size() >= read.min_samples_per_run)
    AddPartialRun(*partial, *recorded);
  out.complete_runs = static_cast<int>(recorded->loaded_samples.size());
  if (recorded->loaded_samples.empty()) {
    out.error = "no complete run to estimate from";
    return out;
  }
  out.estimate = EstimateRecordedSession(std::move(*recorded), *record, limits.fit, threads);
  out.judgement = JudgeRecordedSession(out.estimate.method.summary, *record, limits);
  out.record = std::move(*record);
  return out;
}

// Why a verdict can no longer change with more runs, or nothing: every δ and ξ estimated (none
// held: an estimate conditional on a held value has a std that leaves out the held value's error,
// and after one run of the production sequence it "proved" δ4 of a good unit out of its limits),
// the fit acceptable on the runs so far, and a limit proven non-conforming (the unit fails
// whatever else), or every limit proven conforming or not. An undecided limit (inside a guard
// band), a limit not yet evaluable, a misfit or no limits at all: more runs may change it.
std::optional<std::string> DecidedWhy(const estimator::EstimateSummary& estimate,
                                      const std::optional<Verdict>& verdict) {
  if (!verdict || !verdict->fit_acceptable || verdict->results.empty()) return std::nullopt;
  for (const bool estimated : estimate.delta_estimated)
    if (!estimated) return std::nullopt;
  for (const bool estimated : estimate.xi_estimated)
    if (!estimated) return std::nullopt;
  for (const LimitResult& r : verdict->results) {
    if (r.zone == DecisionZone::kNonConforming)
      return std::string(ToString(r.quantity)) + " proven non-conforming";
  }
  for (const LimitResult& r : verdict->results) {
    if (r.status == LimitStatus::kNotEvaluated || r.zone == DecisionZone::kUndecided)
      return std::nullopt;
  }
  return std::string("every limit decided");
}

void RankNextRuns(LaneJudgement& judged, std::span<const NextRunCandidate> candidates) {
  if (judged.error || !judged.judgement || !judged.judgement->verdict || !judged.record) return;
  const estimator::EstimateSummary& estimate = judged.estimate.method.summary;
  if (DecidedWhy(estimate, judged.judgement->verdict)) return;
  std::vector<estimator::RunPlan> made;
  for (const session::RunRecord& run : judged.record->runs) {
    if (run.status != kRunComplete || !run.plan || !run.end) continue;
    estimator::RunPlan plan;
    const double omega = run.end->values.omega_rad_s;
    plan.omega_rad_s = std::isfinite(omega) ? omega : run.plan->commanded_omega_rad_s;
    plan.a = run.plan->a;
    plan.b = run.plan->b;
    plan.theta_rad = run.plan->theta_rad;
    plan.sample_rate_hz = run.plan->sample_rate_hz;
    plan.duration_s = run.end->samples
                          ? static_cast<double>(*run.end->samples) / plan.sample_rate_hz
                          : run.plan->free_run_s;
    made.push_back(plan);
  }
  judged.next_run_scores =
      NextRunScores(estimate, *judged.judgement->verdict, *judged.record, made, candidates);
}

LookWorker::~LookWorker() {
  if (thread_.joinable()) thread_.join();
}

void LookWorker::Start(std::size_t tag, std::function<LaneJudgement()> look) {
  // One look at a time: a caller that did not take the last one waits for it here, never throws
  // away a running thread (std::terminate).
  if (thread_.joinable()) thread_.join();
  done_.store(false, std::memory_order_relaxed);
  tag_ = tag;
  // Start returns once the look holds the clock: a simulated clock must not run on between this
  // call and the look's first moment (the caller's next sleep would let it).
  thread_ = std::thread([this, look = std::move(look)] {
    clock_.AttachCurrentThread();
    attached_.release();
    try {
      answer_ = look();
    } catch (const std::bad_alloc&) {
      answer_ = LaneJudgement{};
      answer_.error = "the look ran out of memory";
    }
    // Done before the clock is let go: once it is, simulated time runs on, and a caller that polled
    // between the two would see no answer until this thread was scheduled again (on a loaded
    // machine, seconds of simulated time later).
    done_.store(true, std::memory_order_release);
    clock_.DetachCurrentThread();
  });
  attached_.acquire();
}

std::optional<std::pair<std::size_t, LaneJudgement>> LookWorker::TakeIfDone() {
  if (!thread_.joinable() || !done_.load(std::memory_order_acquire)) return std::nullopt;
  thread_.join();
  return std::make_pair(tag_, std::move(answer_));
}

}  // namespace hrgbench::bench::internal
