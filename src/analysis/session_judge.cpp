#include "hrgbench/analysis/session_judge.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "hrgbench/analysis/verdict_json.hpp"

namespace hrgbench::bench {
namespace {

SessionJudgement Error(std::string reason) {
  SessionJudgement judgement;
  judgement.kind = OutcomeKind::kError;
  judgement.reason = std::move(reason);
  return judgement;
}

std::string ShortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", v);
  return text;
}

// Policy step 3: the verdict decides.
SessionJudgement JudgeVerdict(Verdict verdict, const estimator::EngineeringQuantities& engineering,
                              const LimitsConfig& limits) {
  SessionJudgement judgement;
  std::string not_judged;  // "xi2: not evaluated, held fixed ...; delta4: ..."
  for (const LimitResult& r : verdict.results) {
    if (r.status == LimitStatus::kFail)
      judgement.failed_parameters.push_back(
          {std::string(ToString(r.quantity)), r.value, r.min, r.max});
    if (r.status == LimitStatus::kNotEvaluated)
      not_judged += (not_judged.empty() ? "" : "; ") + r.message;
  }
  // Proven outside, and undecided within the guard band (decision_rule.hpp): the operator acts
  // differently on each (scrap or rework; measure again), so the reason names them apart.
  std::string names, undecided;
  for (const LimitResult& r : verdict.results) {
    if (r.status != LimitStatus::kFail) continue;
    std::string& list = r.zone == DecisionZone::kUndecided ? undecided : names;
    list += (list.empty() ? "" : ", ") + std::string(ToString(r.quantity));
  }
  switch (verdict.overall) {
    case LimitStatus::kFail:
      judgement.kind = OutcomeKind::kFail;
      judgement.reason = names.empty() ? std::string() : "out of limits: " + names;
      if (!undecided.empty()) {
        judgement.reason += (judgement.reason.empty() ? "" : "; ") +
                            std::string("not accepted within the guard band (k = ") +
                            ShortNumber(verdict.decision.coverage_factor) + "): " + undecided +
                            (verdict.retest ? ", retest the unit" : "");
      }
      if (!not_judged.empty()) judgement.reason += "; not judged: " + not_judged;
      break;
    case LimitStatus::kNotEvaluated:
      judgement.kind = OutcomeKind::kError;
      judgement.reason =
          verdict.fit_acceptable
              ? "limits not judged: " + not_judged
              : "the fit is outside its model, no limit judged: " + verdict.FitProblems();
      break;
    case LimitStatus::kPass:
      judgement.kind = OutcomeKind::kPass;
      judgement.reason = limits.limits.empty() ? "the fit is within its model; no limits to judge"
                                               : "the fit is within its model and every limit met";
      break;
  }
  judgement.verdict = std::move(verdict);
  judgement.engineering = engineering;
  return judgement;
}

}  // namespace

SessionOutcome SessionJudgement::ToOutcome(std::optional<nlohmann::json> estimate) const {
  SessionOutcome outcome;
  outcome.kind = kind;
  outcome.reason = reason;
  outcome.failed_parameters = failed_parameters;
  outcome.estimate = std::move(estimate);
  if (verdict) outcome.verdict = VerdictJson(*verdict);
  return outcome;
}

SessionJudgement JudgeSession(const estimator::EstimateSummary& estimate,
                              const std::expected<EngineeringOfRecord, std::string>& engineering,
                              const LimitsConfig& limits) {
  if (!estimate.IsUsable()) return Error("estimate not usable: " + estimate.message);
  if (!engineering) return Error("the record's electronics: " + engineering.error());
  const estimator::EngineeringQuantities& quantities = engineering->quantities;
  return JudgeVerdict(EvaluateLimits(limits, estimate, quantities), quantities, limits);
}

SessionJudgement JudgeRecordedSession(const estimator::EstimateSummary& estimate,
                                      const session::SessionRecord& record,
                                      const LimitsConfig& limits) {
  // The engineering of record is computed only for a usable estimate (step 2 follows step 1).
  if (!estimate.IsUsable()) return Error("estimate not usable: " + estimate.message);
  return JudgeSession(estimate, ComputeEngineeringOfRecord(estimate, record), limits);
}

int Severity(OutcomeKind kind) noexcept {
  switch (kind) {
    case OutcomeKind::kPass:
      return 0;
    case OutcomeKind::kFail:
      return 1;
    case OutcomeKind::kError:
      return 2;
    case OutcomeKind::kAborted:
      return 3;
  }
  return 2;
}

OutcomeKind FixtureOutcome(std::span<const OutcomeKind> units) noexcept {
  OutcomeKind worst = OutcomeKind::kPass;
  for (const OutcomeKind kind : units) {
    if (Severity(kind) > Severity(worst)) worst = kind;
  }
  return worst;
}

int FixtureExitCode(std::span<const OutcomeKind> units) noexcept {
  return ExitCode(FixtureOutcome(units));
}

bool KeepsVerdict(bool closed, OutcomeKind kind) noexcept {
  return closed && (kind == OutcomeKind::kPass || kind == OutcomeKind::kFail);
}

std::string KeptReason(std::string_view recorded_reason) {
  return "kept from before: " + std::string(recorded_reason);
}

}  // namespace hrgbench::bench
