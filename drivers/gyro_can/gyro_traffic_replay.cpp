#include "gyro_can/gyro_traffic_replay.hpp"

#include <memory>
#include <string>
#include <utility>

#include "gyro_can/gyro_codec.hpp"
#include "hrgbench/hw/can_frame_text.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

using can_virtual::CanLogPlayback;
using can_virtual::PlaybackFrame;

// A capture reads with a 10 ms timeout (bench/capture.hpp); reading the same way keeps the
// driver's waits what they were live.
constexpr std::int64_t kReadTimeoutNs = 10'000'000;

// The host's commands to `node`; other nodes' commands on a shared bus are not this unit's.
can_virtual::SentByHost HostFramesTo(NodeId node) {
  return [node](const hw::CanFrame& frame) {
    return !frame.extended && !frame.fd && IsCommandId(frame.id) && NodeOf(frame.id) == node;
  };
}

// An Ack answers the command it names, by message and token (a resend repeats the token).
can_virtual::AnswersTo AcksOf(NodeId node) {
  return [node](const hw::CanFrame& sent, const hw::CanFrame& received) {
    Ack ack;
    if (sent.length < 1 || DecodeAck(received, node, &ack) != DecodeStatus::kOk) return false;
    return ack.token == sent.data[0] && CommandMessage(ack.command) == MessageOf(sent.id);
  };
}

class Replayer {
 public:
  Replayer(can_virtual::PlaybackSource source, const GyroReplayOptions& options)
      : bus_(std::move(source), HostFramesTo(options.node), /*supports_fd=*/true,
             AcksOf(options.node)),
        options_(options) {}

  GyroReplay Run() {
    while (const PlaybackFrame* next = bus_.NextSentFrame()) {
      const PlaybackFrame command = *next;
      const std::uint64_t matched = bus_.frames_matched();
      if (!Replay(command)) break;
      ++result_.commands;
      if (bus_.divergence()) break;
      if (bus_.frames_matched() == matched) {
        // The driver refused the call before sending (its state differs from the host's then).
        result_.divergence = At(command) + "the driver did not send the recorded " +
                             hw::CanFrameToString(command.frame) +
                             (result_.notes.empty() ? "" : " (" + result_.notes.back() + ")");
        break;
      }
    }
    if (bus_.divergence() && !result_.divergence) result_.divergence = bus_.divergence();
    result_.frames_matched = bus_.frames_matched();
    result_.frames_delivered = bus_.frames_delivered();
    result_.acks_taken_late = bus_.late_answers();
    return std::move(result_);
  }

 private:
  std::string At(const PlaybackFrame& command) const {
    return "line " + std::to_string(command.line) + ": ";
  }

  void Note(const PlaybackFrame& command, const hw::GyroError& error) {
    result_.notes.push_back(At(command) + error.ToString());
  }

  // A new driver, configured as the host's was: its status rate and frame format are those of the
  // Configure it is about to send (the defaults when its first command is another).
  bool StartDriver(const PlaybackFrame& command) {
    GyroCanDeviceConfig config;
    config.clock = &bus_;
    config.node = options_.node;
    config.ack_timeout_ns = options_.ack_timeout_ns;
    config.command_attempts = options_.command_attempts;
    ConfigureCommand configure;
    if (MessageOf(command.frame.id) == can_id::kConfigure &&
        DecodeConfigure(command.frame, options_.node, &configure) == DecodeStatus::kOk) {
      config.status_rate_hz = configure.status_rate_hz;
      config.prefer_fd = configure.format == FrameFormat::kFd;
    }
    device_.reset();
    auto device = GyroCanDevice::Create(bus_, config);
    if (!device) {
      result_.divergence = At(command) + "the driver cannot start: " + device.error().ToString();
      return false;
    }
    device_ = std::move(*device);
    next_token_ = 0;
    ++result_.host_starts;
    return true;
  }

  bool Replay(const PlaybackFrame& command) {
    const hw::CanFrame& frame = command.frame;
    if (frame.length < 2) {
      result_.divergence = At(command) + "a command without a token";
      return false;
    }
    const std::uint8_t token = frame.data[0];
    if (!device_ || (token == 0 && next_token_ != 0)) {
      if (!StartDriver(command)) return false;
    }
    if (token != next_token_) {
      result_.divergence = At(command) + "the host sent token " + std::to_string(token) +
                           " where the driver's next is " + std::to_string(next_token_) +
                           " (a command the driver did not send, or a repeat it would not make)";
      return false;
    }
    ++next_token_;

    switch (MessageOf(frame.id)) {
      case can_id::kConfigure: {
        ConfigureCommand c;
        if (DecodeConfigure(frame, options_.node, &c) != DecodeStatus::kOk)
          return Undecodable(command);
        if (auto done = device_->Configure({.sample_rate_hz = c.sample_rate_hz}); !done)
          Note(command, done.error());
        return true;
      }
      case can_id::kExcite: {
        ExciteCommand c;
        if (DecodeExcite(frame, options_.node, &c) != DecodeStatus::kOk)
          return Undecodable(command);
        const hw::WaveState wave{c.a_raw * kExciteLsb, c.b_raw * kExciteLsb,
                                 c.theta_raw * kExciteLsb};
        if (auto done = device_->Excite(wave); !done) Note(command, done.error());
        return true;
      }
      case can_id::kStatusRequest: {
        // A host waiting for the wave polls the status; no time left means one poll per call, so
        // the recording decides how many there were.
        if (device_->State() == hw::GyroMode::kExciting) {
          // Between two polls the host took in what arrived (WaitReady pumps until the next
          // poll), so this poll's status is the one that answers it, not one already queued.
          device_->ProcessIncoming(command.stamp_ns - bus_.NowNs());
          auto ready = device_->WaitReady(0);
          if (!ready && ready.error().code != hw::GyroErrorCode::kTimeout)
            Note(command, ready.error());
        } else if (auto status = device_->RequestStatus(); !status) {
          Note(command, status.error());
        }
        return true;
      }
      case can_id::kRelease:
        ReplayRun(command);
        return true;
      case can_id::kStop:
        if (auto done = device_->Stop(); !done) Note(command, done.error());
        return true;
      default:
        return Undecodable(command);
    }
  }

  bool Undecodable(const PlaybackFrame& command) {
    result_.divergence =
        At(command) + "not a valid command of protocol v" + std::to_string(kProtocolVersion);
    return false;
  }

  void ReplayRun(const PlaybackFrame& command) {
    const hw::GyroCounters before = device_->Counters();
    auto released = device_->Release();
    if (!released) {
      Note(command, released.error());
      return;
    }
    ReplayedRun run;
    run.release_line = command.line;
    run.release_t_ns = *released;
    run.sample_rate_hz = device_->sample_rate_hz();
    run.format = device_->frame_format();
    std::vector<hw::GyroSample> batch(options_.read_batch == 0 ? 1 : options_.read_batch);
    for (;;) {
      const hw::GyroReadResult read = device_->ReadSamples(batch, kReadTimeoutNs);
      run.samples.insert(run.samples.end(), batch.begin(),
                         batch.begin() + static_cast<std::ptrdiff_t>(read.count));
      if (bus_.divergence()) break;
      if (read.status == hw::GyroReadStatus::kBusOff || read.status == hw::GyroReadStatus::kError ||
          read.status == hw::GyroReadStatus::kNotRunning)
        break;
      // Everything up to the host's next command is the run's.
      if (read.count == 0 && !bus_.HasDeliverable()) break;
    }
    run.counters = hw::CountersSince(before, device_->Counters());
    result_.runs.push_back(std::move(run));
  }

  CanLogPlayback bus_;
  GyroReplayOptions options_;
  std::unique_ptr<GyroCanDevice> device_;
  std::uint8_t next_token_ = 0;
  GyroReplay result_;
};

}  // namespace

GyroReplay ReplayGyroTraffic(can_virtual::PlaybackSource source, const GyroReplayOptions& options) {
  Replayer replayer(std::move(source), options);
  return replayer.Run();
}

}  // namespace hrgbench::drivers::gyro_can
