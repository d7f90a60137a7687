#pragma once
// CanLogPlayback: a recorded CAN bus played back to a host driver, as an in-process hw::CanBus
// and the hw::Clock of its time. The recording holds both directions (a bus monitor logs every
// frame); a predicate tells the frames the host sent from those it received.
//
//   - Received frames are delivered in the recording's order with their recorded stamps
//     (TimestampSource::kHardware), through the host's filters. A frame recorded after one the
//     host sent is delivered only once the host has sent that frame: a reply never comes before
//     its question.
//   - Sent frames are checked: each Send must be the next frame the host sent in the recording,
//     bit for bit. The first that is not ends the playback (Send returns kError, every later call
//     kError) and divergence() says where: "the driver sent 044#0518 where line 812 of the log has
//     042#0699". This is what lets a driver change be checked against recorded traffic.
//   - Time: NowNs() is the recording's time. Sending a frame moves it to that frame's stamp; a
//     received frame to its stamp. A Receive with nothing deliverable within its timeout (the next
//     frame is the host's, or stamped later than now + timeout, or the recording ended) advances
//     the time by the timeout and returns kTimeout: a host waits for an answer that came late in
//     the recording exactly as long as it waited then, and retries as it retried then.
//     SleepForNs advances the time. Time never goes back (a recording's stamps may: a resumed
//     session's clock offset differs).
//   - An answer taken late: live, a host past its deadline still takes what has already arrived,
//     and a host descheduled longer than its answer was late (a loaded machine) takes an answer
//     stamped after its deadline without resending. The recording holds no look times, only what
//     the host did next; so with an `answers` predicate, an answer to the host's last frame that
//     the recording has before the host's next frame, where that next frame is not a resend of
//     the last, is delivered past the wait (late_answers() counts them). A resend means the host
//     had given up waiting: the wait times out, as above.
//
// The source is pulled one frame at a time, so a recording of any length is played in constant
// memory (the frames between two sent frames that the host has not received yet are held).
//
// Not thread-safe: one thread drives the host and the playback (the hw::Clock is only used by
// it). No error frames, no bus-off, never kBufferFull.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hrgbench/hw/can_bus.hpp"
#include "hrgbench/hw/clock.hpp"

namespace hrgbench::drivers::can_virtual {

struct PlaybackFrame {
  std::int64_t stamp_ns = 0;  // the recording's time base (a candump log: Unix time)
  hw::CanFrame frame;
  std::uint64_t line = 0;  // where it is in the recording (1-based line of a log), for messages
};

// Pulls the next frame of the recording; nullopt at its end.
using PlaybackSource = std::function<std::optional<PlaybackFrame>()>;
// True for frames the host sent.
using SentByHost = std::function<bool(const hw::CanFrame&)>;
// True when `received` answers `sent` (a protocol's acknowledgement of that command).
using AnswersTo = std::function<bool(const hw::CanFrame& sent, const hw::CanFrame& received)>;

class CanLogPlayback final : public hw::CanBus, public hw::Clock {
 public:
  CanLogPlayback(PlaybackSource source, SentByHost sent_by_host, bool supports_fd = true,
                 AnswersTo answers = {});

  // hw::CanBus
  hw::CanStatus Send(const hw::CanFrame& frame, std::int64_t timeout_ns) noexcept override;
  hw::CanStatus Receive(hw::CanFrame* frame, std::int64_t timeout_ns,
                        hw::ReceiveInfo* info) noexcept override;
  hw::CanStatus SetFilters(std::span<const hw::CanFilter> filters) noexcept override;
  hw::CanBusStatistics Statistics() const noexcept override { return statistics_; }
  hw::CanBusState State() const noexcept override { return hw::CanBusState::kErrorActive; }
  bool SupportsFd() const noexcept override { return supports_fd_; }

  // hw::Clock: the recording's time.
  std::int64_t NowNs() const noexcept override { return now_ns_; }
  void SleepForNs(std::int64_t duration_ns) override;

  // The next frame the host sent in the recording that has not been sent yet; nullopt when there
  // is none (the recording ended) or after a divergence.
  const PlaybackFrame* NextSentFrame();
  // A received frame is waiting before the next sent one (whatever its stamp).
  bool HasDeliverable();
  // Recorded host frames sent so far, and received frames delivered so far.
  std::uint64_t frames_matched() const noexcept { return frames_matched_; }
  std::uint64_t frames_delivered() const noexcept { return frames_delivered_; }
  // The line of the last frame delivered or matched (0 before any).
  std::uint64_t line() const noexcept { return line_; }
  const std::optional<std::string>& divergence() const noexcept { return divergence_; }
  // Answers delivered after the host's wait had ended (see above).
  std::uint64_t late_answers() const noexcept { return late_answers_; }

 private:
  // Reads from the source until a sent frame is pending, the source ends, or `received_wanted`
  // received frames are queued.
  void ReadAhead(std::size_t received_wanted);
  bool Accepts(const hw::CanFrame& frame) const noexcept;
  void Advance(std::int64_t stamp_ns) noexcept;
  bool AnswerTakenLate();

  PlaybackSource source_;
  SentByHost sent_by_host_;
  bool supports_fd_ = true;
  AnswersTo answers_;
  std::optional<hw::CanFrame> last_sent_;
  bool last_sent_answered_ = false;
  std::uint64_t late_answers_ = 0;
  bool source_ended_ = false;
  std::deque<PlaybackFrame> received_;  // before pending_sent_ (or the end)
  std::optional<PlaybackFrame> pending_sent_;
  std::vector<hw::CanFilter> filters_;
  std::int64_t now_ns_ = 0;
  bool started_ = false;  // now_ns_ was set from the first frame
  std::uint64_t frames_matched_ = 0;
  std::uint64_t frames_delivered_ = 0;
  std::uint64_t line_ = 0;
  std::optional<std::string> divergence_;
  hw::CanBusStatistics statistics_;
};

}  // namespace hrgbench::drivers::can_virtual
