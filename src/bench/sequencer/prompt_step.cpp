// Operator prompts (sequence [[prompts]]): the bench stops moving before a person is asked to
// act at it, and goes on only on their answer.
//
// Every gyro is stopped and the table brought to rest (idle, zero rate), BEFORE the prompt is
// shown: "mount the unit" or "close the lid" puts hands at the table. Then the prompt is
// recorded in every live unit's record and shown; while it is open the table is read every
// kPollMs (its heartbeat kept, its rate shown as phase "prompt"), the CAN logs pumped and
// interrupts seen. An Abort or Ctrl-C stops the session as any interrupt does (Close records the
// open prompt as interrupted, with the reason); an "abort" answer stops it as ABORTED, naming who.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "bench/sequencer/run_context.hpp"

namespace hrgbench::bench::internal {
namespace {

// Short enough for the panel to show the table's rate live and for any heartbeat period a station
// allows; the answer source waits this long per call.
constexpr std::chrono::milliseconds kPollMs{200};

std::string Quoted(const SequencePrompt& prompt) { return "prompt '" + prompt.id + "'"; }

// Every live unit's record gets the same entry (a fixture's units share the table, so the prompt);
// a unit whose record cannot be written ends on its own fault, the others go on.
void RecordOnEveryUnit(SessionContext& ctx, const auto& write) {
  for (UnitLane& lane : ctx.lanes) {
    if (lane.ended) continue;
    if (auto written = write(*lane.recorder); !written)
      ctx.EndUnit(lane, StepOutcome::Error("record: " + written.error().ToString()));
  }
}

// The table brought to rest in idle mode (zero rate held by the table itself, so no rate command
// is left for a watchdog to guard while the operator works at it), then read until its rate is
// within the settle tolerance of zero and it no longer moves.
StepOutcome BringTableToRest(SessionContext& ctx, const SequencePrompt& prompt) {
  const SequenceConfig& seq = ctx.configs->sequence;
  hw::RateTable& table = *ctx.hw->table;
  hw::Clock& clock = *ctx.hw->clock;
  if (auto stopped = table.Stop(); !stopped)
    return StepOutcome::Error("rate table: cannot stop before " + Quoted(prompt) + ": " +
                              stopped.error().ToString());
  const std::int64_t deadline =
      clock.NowNs() + static_cast<std::int64_t>(seq.timeouts.settle_s * 1e9);
  for (;;) {
    if (ctx.Interrupted())
      return StepOutcome::Aborted(ctx.InterruptCause() + " before " + Quoted(prompt));
    auto status = table.ReadStatus();
    if (!status) return StepOutcome::Error("rate table: " + status.error().ToString());
    if (status->fault)
      return StepOutcome::Error("rate table fault before " + Quoted(prompt) + " (" +
                                hw::RateTableFaultName(status->fault_code) + ")");
    if (std::abs(status->measured_rate_rad_s) <= seq.settle.rate_tolerance_rad_s &&
        !status->in_motion)
      return StepOutcome::Ok();
    if (clock.NowNs() > deadline)
      return StepOutcome::Error("rate table not at rest within " +
                                std::to_string(seq.timeouts.settle_s) + " s before " +
                                Quoted(prompt));
    ctx.PumpCanLogs();
    clock.SleepForNs(static_cast<std::int64_t>(seq.settle.poll_period_s * 1e9));
  }
}

StepOutcome AskOne(SessionContext& ctx, const SequencePrompt& prompt) {
  PromptAnswers* answers = ctx.options->prompts;
  if (answers == nullptr)
    return StepOutcome::Error(Quoted(prompt) + ": nothing answers the sequence's operator prompts");

  // Safe first: the gyros stopped, the table at zero and settled there.
  for (UnitLane& lane : ctx.lanes) {
    if (lane.ended) continue;
    const hw::GyroMode mode = lane.hw->gyro->State();
    if (mode != hw::GyroMode::kIdle && mode != hw::GyroMode::kStopped) StopGyro(*lane.hw);
  }
  if (StepOutcome rest = BringTableToRest(ctx, prompt); !rest.ok()) return rest;

  const PromptRequest request{prompt.id, prompt.Where(), prompt.text, prompt.image_file,
                              prompt.image_sha256};
  RecordOnEveryUnit(ctx, [&](SessionRecorder& recorder) {
    return recorder.BeginPrompt({request.id, request.at, request.text, request.image_sha256});
  });
  if (ctx.LiveUnits() == 0) return StepOutcome::Ok();
  ctx.Log(Quoted(prompt) + " (" + request.at + "): " + prompt.text);
  if (ctx.options->on_prompt) ctx.options->on_prompt(request, nullptr);
  answers->Show(request);

  Progress progress;
  progress.phase = "prompt";
  progress.run_id = prompt.before_run;
  for (bool first = true;; first = false) {
    if (ctx.Interrupted())
      return StepOutcome::Aborted(ctx.InterruptCause() + " while " + Quoted(prompt) + " was open");
    auto status = ctx.hw->table->ReadStatus();
    if (!status) return StepOutcome::Error("rate table: " + status.error().ToString());
    if (status->fault)
      return StepOutcome::Error("rate table fault while " + Quoted(prompt) + " was open (" +
                                hw::RateTableFaultName(status->fault_code) + ")");
    progress.table_rate_rad_s = status->measured_rate_rad_s;
    ctx.ReportProgress(progress, first);  // a change of phase is reported at once
    ctx.PumpCanLogs();
    if (std::optional<PromptReply> reply = answers->Wait(kPollMs)) {
      const PromptAnswered answered{reply->confirmed ? kPromptConfirmed : kPromptAborted, reply->by,
                                    reply->how};
      RecordOnEveryUnit(ctx,
                        [&](SessionRecorder& recorder) { return recorder.EndPrompt(answered); });
      if (ctx.options->on_prompt) ctx.options->on_prompt(request, &*reply);
      const std::string who = reply->by.empty() ? "the operator" : reply->by;
      if (!reply->confirmed)
        return StepOutcome::Aborted("aborted by " + who + " at " + Quoted(prompt));
      ctx.Log(
          Quoted(prompt) +
          (reply->how == "auto" ? " confirmed automatically, by nobody" : " confirmed by " + who) +
          " (" + reply->how + ")");
      return StepOutcome::Ok();
    }
  }
}

}  // namespace

StepOutcome AskOperator(SessionContext& ctx, PromptPoint at, int run_id) {
  for (const SequencePrompt* prompt : ctx.configs->sequence.PromptsAt(at, run_id)) {
    if (ctx.LiveUnits() == 0) break;
    if (StepOutcome asked = AskOne(ctx, *prompt); !asked.ok()) return asked;
  }
  return StepOutcome::Ok();
}

}  // namespace hrgbench::bench::internal
