#include "can_virtual/can_log_playback.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "hrgbench/hw/can_frame_text.hpp"

namespace hrgbench::drivers::can_virtual {
namespace {

using hw::CanStatus;

bool SameFrame(const hw::CanFrame& a, const hw::CanFrame& b) noexcept {
  if (a.id != b.id || a.extended != b.extended || a.fd != b.fd ||
      a.bit_rate_switch != b.bit_rate_switch || a.remote != b.remote || a.error != b.error ||
      a.length != b.length) {
    return false;
  }
  if (a.remote) return true;
  return std::equal(a.data.begin(), a.data.begin() + a.length, b.data.begin());
}

// How far past a wait the recording is searched for the answer and a resend: both come within a
// few frames of the command (a resend within the host's ack timeout), while a sample stream
// behind an answer is unbounded.
constexpr std::size_t kLateAnswerLookAhead = 32;
constexpr std::size_t kUntilNextSent = SIZE_MAX;

}  // namespace

CanLogPlayback::CanLogPlayback(PlaybackSource source, SentByHost sent_by_host, bool supports_fd,
                               AnswersTo answers)
    : source_(std::move(source)),
      sent_by_host_(std::move(sent_by_host)),
      supports_fd_(supports_fd),
      answers_(std::move(answers)) {
  // The recording's time starts at its first frame (a host's first deadline is measured from it).
  ReadAhead(1);
}

void CanLogPlayback::Advance(std::int64_t stamp_ns) noexcept {
  if (!started_ || stamp_ns > now_ns_) now_ns_ = stamp_ns;
  started_ = true;
}

void CanLogPlayback::ReadAhead(std::size_t received_wanted) {
  while (!pending_sent_ && !source_ended_ && received_.size() < received_wanted) {
    std::optional<PlaybackFrame> next = source_();
    if (!next) {
      source_ended_ = true;
      break;
    }
    if (!started_) Advance(next->stamp_ns);
    if (sent_by_host_(next->frame)) {
      pending_sent_ = std::move(next);
    } else if (Accepts(next->frame)) {
      received_.push_back(std::move(*next));
    }
  }
}

bool CanLogPlayback::Accepts(const hw::CanFrame& frame) const noexcept {
  if (filters_.empty()) return true;
  return std::any_of(filters_.begin(), filters_.end(), [&](const hw::CanFilter& f) {
    return f.extended == frame.extended && ((frame.id ^ f.id) & f.mask) == 0;
  });
}

const PlaybackFrame* CanLogPlayback::NextSentFrame() {
  if (divergence_) return nullptr;
  ReadAhead(kUntilNextSent);
  return pending_sent_ ? &*pending_sent_ : nullptr;
}

bool CanLogPlayback::HasDeliverable() {
  if (divergence_) return false;
  ReadAhead(1);
  return !received_.empty();
}

CanStatus CanLogPlayback::Send(const hw::CanFrame& frame, std::int64_t /*timeout_ns*/) noexcept {
  if (divergence_) return CanStatus::kError;
  if (!hw::IsValidCanFrame(frame, supports_fd_)) {
    ++statistics_.invalid_frames;
    return CanStatus::kInvalidFrame;
  }
  ReadAhead(kUntilNextSent);
  if (!pending_sent_) {
    divergence_ = "the driver sent " + hw::CanFrameToString(frame) + " after line " +
                  std::to_string(line_) + ", where the log has no further frame from the host";
  } else if (!SameFrame(frame, pending_sent_->frame)) {
    divergence_ = "the driver sent " + hw::CanFrameToString(frame) + " where line " +
                  std::to_string(pending_sent_->line) + " of the log has " +
                  hw::CanFrameToString(pending_sent_->frame);
  }
  if (divergence_) {
    ++statistics_.send_errors;
    return CanStatus::kError;
  }
  Advance(pending_sent_->stamp_ns);
  line_ = pending_sent_->line;
  last_sent_ = pending_sent_->frame;
  last_sent_answered_ = false;
  pending_sent_.reset();
  ++frames_matched_;
  ++statistics_.frames_sent;
  return CanStatus::kOk;
}

CanStatus CanLogPlayback::Receive(hw::CanFrame* frame, std::int64_t timeout_ns,
                                  hw::ReceiveInfo* info) noexcept {
  if (frame == nullptr) return CanStatus::kInvalidArgument;
  if (divergence_) return CanStatus::kError;
  ReadAhead(1);
  const std::int64_t wait_ns = std::max<std::int64_t>(timeout_ns, 0);
  if (received_.empty()) {
    now_ns_ += wait_ns;
    ++statistics_.timeouts;
    return CanStatus::kTimeout;
  }
  const bool late = received_.front().stamp_ns > now_ns_ + wait_ns;
  if (late && !AnswerTakenLate()) {
    now_ns_ += wait_ns;
    ++statistics_.timeouts;
    return CanStatus::kTimeout;
  }
  PlaybackFrame next = std::move(received_.front());
  received_.pop_front();
  if (answers_ && last_sent_ && answers_(*last_sent_, next.frame)) {
    last_sent_answered_ = true;
    if (late) ++late_answers_;
  }
  Advance(next.stamp_ns);
  line_ = next.line;
  *frame = next.frame;
  if (info != nullptr) {
    info->timestamp_ns = next.stamp_ns;
    info->timestamp_source = hw::TimestampSource::kHardware;
    info->dropped_frames = 0;
  }
  ++frames_delivered_;
  ++statistics_.frames_received;
  return CanStatus::kOk;
}

bool CanLogPlayback::AnswerTakenLate() {
  if (!answers_ || !last_sent_ || last_sent_answered_) return false;
  ReadAhead(kLateAnswerLookAhead);
  // The host resent its frame: it had given up waiting, whatever arrived before the resend.
  if (pending_sent_ && SameFrame(pending_sent_->frame, *last_sent_)) return false;
  const auto end = received_.begin() +
                   static_cast<std::ptrdiff_t>(std::min(received_.size(), kLateAnswerLookAhead));
  return std::any_of(received_.begin(), end,
                     [this](const PlaybackFrame& f) { return answers_(*last_sent_, f.frame); });
}

CanStatus CanLogPlayback::SetFilters(std::span<const hw::CanFilter> filters) noexcept {
  if (filters.size() > hw::kMaxCanFilters) return CanStatus::kInvalidArgument;
  filters_.assign(filters.begin(), filters.end());
  // Frames already read ahead were taken through the old filters; re-filter them.
  std::erase_if(received_, [this](const PlaybackFrame& f) { return !Accepts(f.frame); });
  return CanStatus::kOk;
}

void CanLogPlayback::SleepForNs(std::int64_t duration_ns) {
  if (duration_ns > 0) now_ns_ += duration_ns;
}

}  // namespace hrgbench::drivers::can_virtual
