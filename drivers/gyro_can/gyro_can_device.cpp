#include "gyro_can/gyro_can_device.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "hrgbench/hw/error_text.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

using hw::CanStatus;
using hw::GyroError;
using hw::GyroErrorCode;
using hw::GyroMode;

// Where nothing drives the wave or reads it: a run may be configured and the parameter block read
// or written (never under a wave the electronics are using it for).
constexpr std::array<GyroMode, 3> kNoWaveModes = {GyroMode::kIdle, GyroMode::kConfigured,
                                                  GyroMode::kStopped};

std::string Hex2(unsigned value) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  return {kHex[(value >> 4) & 0xFu], kHex[value & 0xFu]};
}

std::unexpected<GyroError> Fail(GyroErrorCode code, std::string message) {
  return std::unexpected(GyroError{code, std::move(message)});
}

const char* CommandName(Command command) {
  switch (command) {
    case Command::kConfigure:
      return "configure";
    case Command::kExcite:
      return "excite";
    case Command::kRelease:
      return "release";
    case Command::kStop:
      return "stop";
    case Command::kStatusRequest:
      return "status request";
    case Command::kParameter:
      return "parameter";
  }
  return "?";
}

const char* ResultName(AckResult result) {
  switch (result) {
    case AckResult::kOk:
      return "ok";
    case AckResult::kBadState:
      return "bad state";
    case AckResult::kBadArgument:
      return "bad argument";
    case AckResult::kFaulted:
      return "faulted";
  }
  return "?";
}

hw::GyroStatus ToGyroStatus(const StatusMessage& message, std::int64_t t_ns) {
  hw::GyroStatus status;
  status.t_ns = t_ns;
  status.mode = message.mode;
  status.fault_bits = message.fault_bits;
  status.pll_lock = message.pll_lock;
  status.ready = message.ready;
  status.resonant_frequency_hz = message.frequency_mhz * kFrequencyLsbHz;
  status.temperature_c = message.temperature_centi_c * kTemperatureLsbC;
  return status;
}

}  // namespace

bool GyroCanDeviceConfig::IsValid(std::string* why) const {
  const auto fail = [why](std::string message) {
    if (why != nullptr) *why = std::move(message);
    return false;
  };
  if (clock == nullptr) return fail("clock must be set (the transport's time base)");
  if (node > kMaxNodeId) {
    return fail(hw::ErrorText("node must be in 0..", static_cast<int>(kMaxNodeId), ", got ",
                              static_cast<int>(node)));
  }
  if (ack_timeout_ns <= 0)
    return fail(hw::ErrorText("ack_timeout_ns must be > 0, got ", ack_timeout_ns));
  if (command_attempts < 1 || command_attempts > 10) {
    return fail(hw::ErrorText("command_attempts must be in 1..10, got ", command_attempts));
  }
  if (status_poll_ns <= 0)
    return fail(hw::ErrorText("status_poll_ns must be > 0, got ", status_poll_ns));
  if (sample_buffer_capacity < kSamplesPerFdFrame) {
    return fail(hw::ErrorText("sample_buffer_capacity must be >= ", kSamplesPerFdFrame, ", got ",
                              sample_buffer_capacity));
  }
  return true;
}

std::expected<std::unique_ptr<GyroCanDevice>, GyroError> GyroCanDevice::Create(
    hw::CanBus& bus, const GyroCanDeviceConfig& config) {
  std::string why;
  if (!config.IsValid(&why)) return Fail(GyroErrorCode::kInvalidArgument, why);
  // The node's Ack and Status (0x08n, 0x09n), samples and reference phase (0x10n … 0x13n).
  static_assert(can_id::kStatus == (can_id::kAck | 0x010) &&
                can_id::kReferencePhase == (can_id::kSampleA | 0x030));
  // The operating stream and its loops' reports: 0x14n … 0x17n (0x17n is no message: unexpected).
  static_assert(can_id::kOperatingLoopsA == (can_id::kOperatingSample | 0x010) &&
                can_id::kOperatingLoopsB == (can_id::kOperatingSample | 0x020));
  const std::array<hw::CanFilter, 3> filters = {
      hw::CanFilter{NodeMessageId(can_id::kAck, config.node), 0x7EF, false},
      hw::CanFilter{NodeMessageId(can_id::kSampleA, config.node), 0x7CF, false},
      hw::CanFilter{NodeMessageId(can_id::kOperatingSample, config.node), 0x7CF, false}};
  if (const CanStatus status = bus.SetFilters(filters); status != CanStatus::kOk) {
    return Fail(GyroErrorCode::kTransport,
                hw::ErrorText("setting CAN filters failed: ", hw::ToString(status)));
  }
  return std::unique_ptr<GyroCanDevice>(new GyroCanDevice(bus, config));
}

GyroCanDevice::GyroCanDevice(hw::CanBus& bus, const GyroCanDeviceConfig& config)
    : bus_(bus),
      config_(config),
      clock_(*config.clock),
      decoder_(config.sample_buffer_capacity),
      operating_buffer_(std::max<std::size_t>(config.sample_buffer_capacity, 1)) {}

std::expected<void, GyroError> GyroCanDevice::RequireState(std::span<const GyroMode> allowed,
                                                           const char* what) const {
  const GyroMode now = State();
  if (std::find(allowed.begin(), allowed.end(), now) != allowed.end()) return {};
  return Fail(GyroErrorCode::kInvalidState,
              hw::ErrorText(what, " is not allowed in state ", hw::ToString(now)));
}

void GyroCanDevice::OnBusOff() noexcept {
  counters_.bus_errors.fetch_add(1, std::memory_order_relaxed);
  streaming_ = false;
  SetState(GyroMode::kFaulted);
}

void GyroCanDevice::SyncDecoderCounters() noexcept {
  const SampleStreamCounters& c = decoder_.counters();
  counters_.samples_decoded.store(c.samples_decoded, std::memory_order_relaxed);
  counters_.sequence_gaps.store(c.sequence_gaps, std::memory_order_relaxed);
  counters_.samples_lost.store(c.samples_lost, std::memory_order_relaxed);
  counters_.buffer_overruns.store(c.buffer_overruns, std::memory_order_relaxed);
  counters_.reference_phases_missing.store(c.reference_phases_missing, std::memory_order_relaxed);
}

void GyroCanDevice::ProcessFrame(const hw::CanFrame& frame, const hw::ReceiveInfo& info) noexcept {
  // Another node's traffic on a shared bus (a transport that does not filter): not this unit's.
  if (!frame.error && !frame.extended && IsElectronicsId(frame.id) &&
      NodeOf(frame.id) != config_.node) {
    return;
  }
  counters_.frames_received.fetch_add(1, std::memory_order_relaxed);
  if (info.dropped_frames != 0) {
    counters_.kernel_drops.fetch_add(info.dropped_frames, std::memory_order_relaxed);
  }
  const NodeId node = config_.node;
  const std::uint32_t message = MessageOf(frame.id);
  DecodeStatus status = DecodeStatus::kWrongId;
  if (frame.error || frame.extended || NodeOf(frame.id) != node) {
    counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  if (message == can_id::kSampleA || message == can_id::kSampleB) {
    SampleHalf half;
    status = DecodeSampleHalf(frame, node, &half);
    if (status == DecodeStatus::kOk) {
      if (!streaming_ || format_ != FrameFormat::kClassic) {
        counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);
        return;
      }
      decoder_.OnSampleHalf(half, info.timestamp_ns);
      SyncDecoderCounters();
      return;
    }
  } else if (message == can_id::kSampleFd) {
    SampleFdBlock block;
    status = DecodeSampleFd(frame, node, &block);
    if (status == DecodeStatus::kOk) {
      if (!streaming_ || format_ != FrameFormat::kFd) {
        counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);
        return;
      }
      decoder_.OnSampleFd(block, info.timestamp_ns);
      SyncDecoderCounters();
      return;
    }
  } else if (message == can_id::kReferencePhase) {
    ReferencePhaseReport report;
    status = DecodeReferencePhase(frame, node, &report);
    if (status == DecodeStatus::kOk) {
      if (!streaming_) {
        counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);
        return;
      }
      decoder_.OnReferencePhase(report, info.timestamp_ns);
      return;
    }
  } else if (message == can_id::kOperatingSample) {
    OperatingSampleFrame sample;
    status = DecodeOperatingSample(frame, node, &sample);
    if (status == DecodeStatus::kOk) {
      if (!streaming_ || !whole_angle_) {
        counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);
        return;
      }
      OnOperatingSample(sample);
      return;
    }
  } else if (message == can_id::kOperatingLoopsA || message == can_id::kOperatingLoopsB) {
    OperatingLoopsHalf half;
    status = DecodeOperatingLoopsHalf(frame, node, &half);
    if (status == DecodeStatus::kOk) {
      if (!streaming_ || !whole_angle_) {
        counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);
        return;
      }
      OnOperatingLoops(half);
      return;
    }
  } else if (message == can_id::kAck) {
    Ack ack;
    status = DecodeAck(frame, node, &ack);
    if (status == DecodeStatus::kOk) {
      if (awaiting_ack_ && !ack_received_ && ack.command == awaited_command_ &&
          ack.token == awaited_token_) {
        ack_ = ack;
        ack_stamp_ns_ = info.timestamp_ns;
        ack_received_ = true;
      } else {
        // A repeated Ack of an earlier attempt, or an answer to someone else's command.
        counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);
      }
      return;
    }
  } else if (message == can_id::kStatus) {
    StatusMessage reported;
    status = DecodeStatusMessage(frame, node, &reported);
    if (status == DecodeStatus::kOk) {
      const hw::GyroStatus decoded = ToGyroStatus(reported, info.timestamp_ns);
      decoder_.OnStatus(decoded.temperature_c, decoded.resonant_frequency_hz);
      {
        const std::lock_guard lock(status_mutex_);
        last_status_ = decoded;
      }
      ++status_frames_;
      if (reported.mode == GyroMode::kFaulted && State() != GyroMode::kStopped) {
        streaming_ = false;
        SetState(GyroMode::kFaulted);
      }
      return;
    }
  } else {
    counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  counters_.bad_frames.fetch_add(1, std::memory_order_relaxed);
}

template <typename Done>
CanStatus GyroCanDevice::PumpUntil(std::int64_t deadline_ns, Done done) noexcept {
  hw::CanFrame frame;
  hw::ReceiveInfo info;
  while (!done()) {
    // Past the deadline, still take what has already arrived (a wait may end at the deadline
    // with the awaited frame queued behind others): only an empty queue is a timeout.
    const std::int64_t remaining = std::max<std::int64_t>(deadline_ns - clock_.NowNs(), 0);
    const CanStatus status = bus_.Receive(&frame, remaining, &info);
    if (status == CanStatus::kOk) {
      ProcessFrame(frame, info);
    } else if (status != CanStatus::kTimeout) {
      return status;
    } else if (remaining == 0 || clock_.NowNs() >= deadline_ns) {
      return CanStatus::kTimeout;
    }
  }
  return CanStatus::kOk;
}

template <typename Encode>
std::expected<Ack, GyroError> GyroCanDevice::Transact(Command command, Encode encode) {
  const std::uint8_t token = next_token_++;
  const hw::CanFrame frame = encode(token);
  awaited_command_ = command;
  awaited_token_ = token;
  ack_received_ = false;
  awaiting_ack_ = true;
  struct Reset {
    bool* flag;
    ~Reset() { *flag = false; }
  } reset{&awaiting_ack_};

  for (int attempt = 1; attempt <= config_.command_attempts; ++attempt) {
    if (attempt > 1) counters_.command_retries.fetch_add(1, std::memory_order_relaxed);
    const CanStatus sent = bus_.Send(frame, config_.ack_timeout_ns);
    if (sent == CanStatus::kBusOff) {
      OnBusOff();
      return Fail(GyroErrorCode::kBusOff, hw::ErrorText(CommandName(command), ": bus-off on send"));
    }
    if (sent != CanStatus::kOk && sent != CanStatus::kBufferFull) {
      counters_.bus_errors.fetch_add(1, std::memory_order_relaxed);
      return Fail(GyroErrorCode::kTransport,
                  hw::ErrorText(CommandName(command), ": send failed: ", hw::ToString(sent)));
    }
    const CanStatus waited =
        PumpUntil(clock_.NowNs() + config_.ack_timeout_ns, [this] { return ack_received_; });
    if (waited == CanStatus::kOk) break;
    if (waited == CanStatus::kBusOff) {
      OnBusOff();
      return Fail(GyroErrorCode::kBusOff,
                  hw::ErrorText(CommandName(command), ": bus-off while waiting for the ack"));
    }
    if (waited != CanStatus::kTimeout) {
      counters_.bus_errors.fetch_add(1, std::memory_order_relaxed);
      return Fail(GyroErrorCode::kTransport,
                  hw::ErrorText(CommandName(command), ": receive failed: ", hw::ToString(waited)));
    }
    counters_.timeouts.fetch_add(1, std::memory_order_relaxed);
  }
  if (!ack_received_) {
    return Fail(GyroErrorCode::kTimeout,
                hw::ErrorText(CommandName(command), " (token ", static_cast<int>(token),
                              "): no ack after ", config_.command_attempts, " attempts of ",
                              config_.ack_timeout_ns / 1'000'000, " ms"));
  }
  if (ack_.result != AckResult::kOk) {
    counters_.nacks.fetch_add(1, std::memory_order_relaxed);
    if (ack_.result == AckResult::kFaulted) {
      SetState(GyroMode::kFaulted);
      return Fail(GyroErrorCode::kFaulted,
                  hw::ErrorText(CommandName(command), ": electronics faulted (mode ",
                                hw::ToString(ack_.mode), ")"));
    }
    return Fail(GyroErrorCode::kRejected,
                hw::ErrorText(CommandName(command), ": rejected (", ResultName(ack_.result),
                              ") in electronics mode ", hw::ToString(ack_.mode)));
  }
  return ack_;
}

std::expected<void, GyroError> GyroCanDevice::Configure(const hw::GyroConfig& config) {
  if (auto ok = RequireState(kNoWaveModes, "configure"); !ok) {
    return ok;
  }
  const FrameFormat format =
      config_.prefer_fd && bus_.SupportsFd() ? FrameFormat::kFd : FrameFormat::kClassic;
  const std::uint32_t max_rate =
      format == FrameFormat::kFd ? kMaxFdSampleRateHz : kMaxClassicSampleRateHz;
  if (config.sample_rate_hz < 1 || config.sample_rate_hz > max_rate) {
    return Fail(GyroErrorCode::kInvalidArgument,
                hw::ErrorText("sample_rate_hz must be in 1..", max_rate, " on ",
                              format == FrameFormat::kFd ? "FD" : "classic", " CAN, got ",
                              config.sample_rate_hz));
  }
  const ConfigureCommand command{
      .token = 0,
      .sample_rate_hz = static_cast<std::uint16_t>(config.sample_rate_hz),
      .format = format,
      .status_rate_hz = config_.status_rate_hz,
      .run_mode = config.whole_angle ? RunMode::kWholeAngle : RunMode::kFreeRun};
  auto ack = Transact(Command::kConfigure, [&](std::uint8_t token) {
    ConfigureCommand c = command;
    c.token = token;
    return EncodeConfigure(config_.node, c);
  });
  if (!ack) return std::unexpected(ack.error());
  if (ack->arg != config.sample_rate_hz || ack->mode != GyroMode::kConfigured) {
    return Fail(
        GyroErrorCode::kReadBackMismatch,
        hw::ErrorText("configure: asked ", config.sample_rate_hz, " Hz, electronics acknowledged ",
                      ack->arg, " Hz in mode ", hw::ToString(ack->mode)));
  }
  format_ = format;
  sample_rate_hz_ = config.sample_rate_hz;
  whole_angle_ = config.whole_angle;
  SetState(GyroMode::kConfigured);
  return {};
}

std::expected<void, GyroError> GyroCanDevice::Excite(const hw::WaveState& target) {
  if (auto ok = RequireState(std::array{GyroMode::kConfigured, GyroMode::kReady}, "excite"); !ok)
    return ok;
  const double a_max = 65535 * kExciteLsb;
  const double bt_max = 32767 * kExciteLsb;
  if (!std::isfinite(target.a) || !std::isfinite(target.b) || !std::isfinite(target.theta_rad) ||
      target.a <= 0 || target.a > a_max || std::abs(target.b) >= target.a ||
      std::abs(target.b) > bt_max || std::abs(target.theta_rad) > bt_max) {
    return Fail(
        GyroErrorCode::kInvalidArgument,
        hw::ErrorText("excite: need 0 < a <= ", a_max, ", |b| < a, |b|, |theta| <= ", bt_max,
                      "; got a=", target.a, " b=", target.b, " theta_rad=", target.theta_rad));
  }
  ExciteCommand command;
  command.a_raw = static_cast<std::uint16_t>(std::lround(target.a / kExciteLsb));
  command.b_raw = static_cast<std::int16_t>(std::lround(target.b / kExciteLsb));
  command.theta_raw = static_cast<std::int16_t>(std::lround(target.theta_rad / kExciteLsb));
  auto ack = Transact(Command::kExcite, [&](std::uint8_t token) {
    ExciteCommand c = command;
    c.token = token;
    return EncodeExcite(config_.node, c);
  });
  if (!ack) return std::unexpected(ack.error());
  if (ack->mode != GyroMode::kExciting && ack->mode != GyroMode::kReady) {
    return Fail(GyroErrorCode::kReadBackMismatch,
                hw::ErrorText("excite: acknowledged in mode ", hw::ToString(ack->mode)));
  }
  SetState(GyroMode::kExciting);
  return {};
}

std::expected<hw::GyroStatus, GyroError> GyroCanDevice::RequestStatus() {
  if (State() == GyroMode::kFaulted && bus_.State() == hw::CanBusState::kBusOff) {
    return Fail(GyroErrorCode::kBusOff, "status request: the bus is off");
  }
  const std::uint64_t seen = status_frames_;
  auto ack = Transact(Command::kStatusRequest, [this](std::uint8_t token) {
    return EncodeSimpleCommand(config_.node, {Command::kStatusRequest, token});
  });
  if (!ack) return std::unexpected(ack.error());
  const CanStatus waited = PumpUntil(clock_.NowNs() + config_.ack_timeout_ns,
                                     [this, seen] { return status_frames_ != seen; });
  if (waited == CanStatus::kBusOff) {
    OnBusOff();
    return Fail(GyroErrorCode::kBusOff, "status request: bus-off while waiting for the status");
  }
  if (waited != CanStatus::kOk) {
    counters_.timeouts.fetch_add(1, std::memory_order_relaxed);
    return Fail(GyroErrorCode::kTimeout,
                "status request acknowledged but no status frame followed");
  }
  return LastStatus();
}

std::expected<hw::GyroStatus, GyroError> GyroCanDevice::WaitReady(std::int64_t timeout_ns) {
  if (auto ok = RequireState(std::array{GyroMode::kExciting, GyroMode::kReady}, "wait ready");
      !ok) {
    return std::unexpected(ok.error());
  }
  const std::int64_t deadline_ns = clock_.NowNs() + std::max<std::int64_t>(timeout_ns, 0);
  for (;;) {
    auto status = RequestStatus();
    if (!status) return status;
    if (status->mode == GyroMode::kFaulted || status->fault_bits != 0) {
      SetState(GyroMode::kFaulted);
      return Fail(GyroErrorCode::kFaulted,
                  hw::ErrorText("wait ready: electronics report mode ", hw::ToString(status->mode),
                                " with fault bits 0x", Hex2(status->fault_bits)));
    }
    if (status->mode == GyroMode::kReady && status->ready) {
      SetState(GyroMode::kReady);
      return status;
    }
    const std::int64_t now = clock_.NowNs();
    if (now >= deadline_ns) {
      return Fail(GyroErrorCode::kTimeout,
                  hw::ErrorText("wait ready: not ready after ", timeout_ns / 1'000'000,
                                " ms (mode ", hw::ToString(status->mode), ")"));
    }
    // Keep consuming frames (periodic status) while waiting for the next poll.
    const CanStatus waited =
        PumpUntil(std::min(deadline_ns, now + config_.status_poll_ns), [] { return false; });
    if (waited == CanStatus::kBusOff) {
      OnBusOff();
      return Fail(GyroErrorCode::kBusOff, "wait ready: bus-off");
    }
  }
}

CanStatus GyroCanDevice::ProcessIncoming(std::int64_t timeout_ns) noexcept {
  const CanStatus status =
      PumpUntil(clock_.NowNs() + std::max<std::int64_t>(timeout_ns, 0), [] { return false; });
  if (status == CanStatus::kBusOff) OnBusOff();
  return status;
}

std::expected<std::int64_t, GyroError> GyroCanDevice::Release() {
  if (auto ok = RequireState(std::array{GyroMode::kReady}, "release"); !ok)
    return std::unexpected(ok.error());
  // Samples may follow the Ack immediately (or precede a repeated Ack): be ready for them first.
  decoder_.Start(format_, sample_rate_hz_);
  operating_count_ = 0;
  operating_head_ = 0;
  operating_started_ = false;
  loops_half_pending_ = false;
  loops_ = {};
  streaming_ = true;
  auto ack = Transact(Command::kRelease, [this](std::uint8_t token) {
    return EncodeSimpleCommand(config_.node, {Command::kRelease, token});
  });
  if (!ack) {
    streaming_ = false;
    return std::unexpected(ack.error());
  }
  const GyroMode expected = whole_angle_ ? GyroMode::kOperating : GyroMode::kFreeRun;
  if (ack->mode != expected) {
    streaming_ = false;
    return Fail(GyroErrorCode::kReadBackMismatch,
                hw::ErrorText("release: acknowledged in mode ", hw::ToString(ack->mode),
                              ", expected ", hw::ToString(expected)));
  }
  const std::int64_t t0_ns = ack_stamp_ns_ - static_cast<std::int64_t>(ack->arg) * 1000;
  decoder_.SetReleaseTime(t0_ns);
  SetState(expected);
  return t0_ns;
}

std::expected<void, GyroError> GyroCanDevice::Stop() {
  auto ack = Transact(Command::kStop, [this](std::uint8_t token) {
    return EncodeSimpleCommand(config_.node, {Command::kStop, token});
  });
  streaming_ = false;
  if (!ack) {
    SetState(GyroMode::kFaulted);
    return std::unexpected(ack.error());
  }
  if (ack->mode != GyroMode::kStopped) {
    SetState(GyroMode::kFaulted);
    return Fail(GyroErrorCode::kReadBackMismatch,
                hw::ErrorText("stop: acknowledged in mode ", hw::ToString(ack->mode)));
  }
  SetState(GyroMode::kStopped);
  return {};
}

void GyroCanDevice::OnOperatingSample(const OperatingSampleFrame& frame) noexcept {
  // The sample's number from its 8-bit counter: the first at or after the one expected (a loss of
  // 256 samples in a row would alias; the operating stream is checked by its angle, not its y).
  std::uint64_t index = 0;
  if (operating_started_) {
    const auto step = static_cast<std::uint8_t>(frame.seq - operating_last_seq_);
    if (step == 0) {
      counters_.unexpected_frames.fetch_add(1, std::memory_order_relaxed);  // a repeat
      return;
    }
    index = operating_last_index_ + step;
    if (step != 1) counters_.sequence_gaps.fetch_add(1, std::memory_order_relaxed);
  } else {
    index = frame.seq;
  }
  operating_started_ = true;
  operating_last_seq_ = frame.seq;
  operating_last_index_ = index;
  if (operating_count_ == operating_buffer_.size()) {
    counters_.buffer_overruns.fetch_add(1, std::memory_order_relaxed);  // the oldest is lost
    operating_head_ = (operating_head_ + 1) % operating_buffer_.size();
    --operating_count_;
  }
  hw::OperatingSample& out =
      operating_buffer_[(operating_head_ + operating_count_) % operating_buffer_.size()];
  out.index = index;
  out.angle_output_rad = frame.angle_output_raw * kAngleOutputLsbRad;
  out.wave_angle_rad = frame.wave_angle_raw * kWaveAngleLsbRad;
  ++operating_count_;
}

void GyroCanDevice::OnOperatingLoops(const OperatingLoopsHalf& half) noexcept {
  if (half.half == 0) {
    if (loops_half_pending_) ++loops_.incomplete;  // the earlier A's B was lost
    loops_pending_ = half;
    loops_half_pending_ = true;
    return;
  }
  if (!loops_half_pending_ || loops_pending_.seq != half.seq) {
    if (loops_half_pending_) ++loops_.incomplete;  // that A's B, and this B's A, were lost
    ++loops_.incomplete;
    loops_half_pending_ = false;
    return;
  }
  loops_half_pending_ = false;
  // The report follows its sample's OperatingSample: its number is the operating sample's nearest
  // to its seq (a signed 8-bit difference; before any operating sample, the seq itself).
  std::uint64_t index = half.seq;
  if (operating_started_) {
    const int back = static_cast<std::int8_t>(operating_last_seq_ - half.seq);
    if (back < 0) {
      index = operating_last_index_ + static_cast<std::uint64_t>(-back);  // its sample was lost
    } else if (static_cast<std::uint64_t>(back) <= operating_last_index_) {
      index = operating_last_index_ - static_cast<std::uint64_t>(back);
    }
  }
  hw::OperatingLoops report;
  report.index = index;
  report.energy_error = loops_pending_.value_raw[0] * kEnergyErrorLsb;
  report.quadrature_ratio = loops_pending_.value_raw[1] * kQuadratureRatioLsb;
  report.amplitude_effort_per_s = half.value_raw[0] * kLoopEffortLsb;
  report.quadrature_effort_rad_s = half.value_raw[1] * kLoopEffortLsb;
  ++loops_.reports;
  loops_.last = report;
  loops_.max_abs_energy_error =
      std::max(loops_.max_abs_energy_error, std::abs(report.energy_error));
  loops_.max_abs_quadrature_ratio =
      std::max(loops_.max_abs_quadrature_ratio, std::abs(report.quadrature_ratio));
  const double fields[4] = {report.energy_error, report.quadrature_ratio,
                            report.amplitude_effort_per_s, report.quadrature_effort_rad_s};
  for (std::size_t i = 0; i < 4; ++i) {
    loops_.sum[i] += fields[i];
    loops_.sum_of_squares[i] += fields[i] * fields[i];
  }
}

std::size_t GyroCanDevice::ReadOperatingSamples(std::span<hw::OperatingSample> out,
                                                std::int64_t timeout_ns) noexcept {
  const std::int64_t deadline_ns = clock_.NowNs() + std::max<std::int64_t>(timeout_ns, 0);
  std::size_t n = 0;
  while (n < out.size()) {
    while (n < out.size() && operating_count_ > 0) {
      out[n++] = operating_buffer_[operating_head_];
      operating_head_ = (operating_head_ + 1) % operating_buffer_.size();
      --operating_count_;
    }
    if (n == out.size() || !streaming_) break;
    const CanStatus status =
        PumpUntil(deadline_ns, [this] { return operating_count_ > 0 || !streaming_; });
    if (status != CanStatus::kOk) {
      if (status == CanStatus::kBusOff) OnBusOff();
      break;
    }
  }
  return n;
}

std::expected<std::uint32_t, GyroError> GyroCanDevice::ParameterTransact(ParameterOp op,
                                                                         std::uint8_t index,
                                                                         std::uint16_t value) {
  auto ack = Transact(Command::kParameter, [this, op, index, value](std::uint8_t token) {
    return EncodeParameter(config_.node, {token, op, index, value});
  });
  if (!ack) return std::unexpected(ack.error());
  return ack->arg;
}

std::expected<ParameterBlockWords, GyroError> GyroCanDevice::ReadParameterWords(ParameterOp op) {
  ParameterBlockWords words{};
  for (int i = 0; i < kParameterBlockWords; ++i) {
    const auto index = static_cast<std::uint8_t>(i);
    auto arg = ParameterTransact(op, index, 0);
    if (!arg) return std::unexpected(arg.error());
    if ((*arg >> 16) != index) {
      return Fail(
          GyroErrorCode::kReadBackMismatch,
          hw::ErrorText("parameter read: asked for word ", i, ", answered word ", *arg >> 16));
    }
    words[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(*arg & 0xFFFFu);
  }
  return words;
}

std::expected<ParameterValues, GyroError> GyroCanDevice::ReadParameters() {
  if (auto ok = RequireState(kNoWaveModes, "read parameters"); !ok) {
    return std::unexpected(ok.error());
  }
  auto words = ReadParameterWords(ParameterOp::kReadActive);
  if (!words) return std::unexpected(words.error());
  ParameterValues values{};
  if (const auto status = DecodeParameterBlock(*words, &values);
      status != ParameterBlockStatus::kOk) {
    return Fail(
        GyroErrorCode::kReadBackMismatch,
        hw::ErrorText("read parameters: the active block is not valid: ", ToString(status)));
  }
  return values;
}

std::expected<hw::CompensationWrite, GyroError> GyroCanDevice::WriteParameters(
    const ParameterValues& values) {
  if (auto ok = RequireState(kNoWaveModes, "write parameters"); !ok) {
    return std::unexpected(ok.error());
  }
  const ParameterBlockWords block = EncodeParameterBlock(values);
  ParameterValues check{};
  if (DecodeParameterBlock(block, &check) != ParameterBlockStatus::kOk) {
    return Fail(GyroErrorCode::kInvalidArgument, "write parameters: a value is not finite");
  }
  hw::CompensationWrite outcome;
  // What the unit held before, so that the record can restore it.
  if (auto before = ReadParameterWords(ParameterOp::kReadActive); !before) {
    return std::unexpected(before.error());
  } else if (ParameterValues previous{};
             DecodeParameterBlock(*before, &previous) == ParameterBlockStatus::kOk) {
    outcome.previous = previous;
  }
  if (auto begun = ParameterTransact(ParameterOp::kBegin, 0, kParameterBlockWords); !begun) {
    return std::unexpected(begun.error());
  }
  for (int i = 0; i < kParameterBlockWords; ++i) {
    auto written = ParameterTransact(ParameterOp::kWrite, static_cast<std::uint8_t>(i),
                                     block[static_cast<std::size_t>(i)]);
    if (!written) return std::unexpected(written.error());
  }
  // Read back what the electronics staged before anything is committed: a word changed on the way
  // (or in their memory) leaves the committed block as it was.
  auto staged = ReadParameterWords(ParameterOp::kReadStaged);
  if (!staged) return std::unexpected(staged.error());
  for (int i = 0; i < kParameterBlockWords; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if ((*staged)[k] != block[k]) {
      return Fail(GyroErrorCode::kReadBackMismatch,
                  hw::ErrorText("write parameters: staged word ", i, " reads ", (*staged)[k],
                                ", written ", block[k], "; nothing committed"));
    }
  }
  auto generation = ParameterTransact(ParameterOp::kCommit, 0, 0);
  if (!generation) {
    // No confirmed commit (a power loss shows as no Ack, or as a retry the restarted electronics
    // refuse): say which block they hold now, as far as they can be read.
    GyroError error = generation.error();
    auto held = ReadParameterWords(ParameterOp::kReadActive);
    ParameterValues held_values{};
    if (!held) {
      error.message += "; what the electronics hold could not be read: " + held.error().message;
    } else if (*held == block) {
      error.message += "; the electronics hold the new block all the same";
    } else if (DecodeParameterBlock(*held, &held_values) != ParameterBlockStatus::kOk) {
      error.message += "; the electronics hold no valid block";
    } else if (outcome.previous && held_values == *outcome.previous) {
      error.message += "; the electronics hold the block before, unchanged";
    } else {
      error.message +=
          "; the electronics hold a block that is neither the new one nor the one before";
    }
    return std::unexpected(error);
  }
  outcome.generation = *generation;
  // And what the non-volatile memory now holds.
  auto active = ReadParameterWords(ParameterOp::kReadActive);
  if (!active) return std::unexpected(active.error());
  if (*active != block) {
    return Fail(GyroErrorCode::kReadBackMismatch,
                hw::ErrorText("write parameters: committed generation ", outcome.generation,
                              " but the active block differs from the one written"));
  }
  return outcome;
}

std::expected<std::uint32_t, GyroError> GyroCanDevice::RestorePreviousParameters() {
  if (auto ok = RequireState(kNoWaveModes, "restore parameters"); !ok) {
    return std::unexpected(ok.error());
  }
  return ParameterTransact(ParameterOp::kRestore, 0, 0);
}

hw::GyroReadResult GyroCanDevice::ReadSamples(std::span<hw::GyroSample> out,
                                              std::int64_t timeout_ns) noexcept {
  std::size_t n = decoder_.Pop(out);
  SyncDecoderCounters();  // Pop counts the samples it gives up waiting for their reference phase
  if (n == out.size()) return {n, hw::GyroReadStatus::kOk};
  if (!streaming_) return {n, n > 0 ? hw::GyroReadStatus::kOk : hw::GyroReadStatus::kNotRunning};
  const std::int64_t deadline_ns = clock_.NowNs() + std::max<std::int64_t>(timeout_ns, 0);
  hw::CanFrame frame;
  hw::ReceiveInfo info;
  for (;;) {
    // Once something is in hand, only drain what has already arrived.
    const std::int64_t wait_ns =
        n > 0 ? 0 : std::max<std::int64_t>(deadline_ns - clock_.NowNs(), 0);
    const CanStatus status = bus_.Receive(&frame, wait_ns, &info);
    if (status == CanStatus::kOk) {
      ProcessFrame(frame, info);
      n += decoder_.Pop(out.subspan(n));
      SyncDecoderCounters();
      if (n == out.size()) return {n, hw::GyroReadStatus::kOk};
      if (!streaming_ && n == 0) return {0, hw::GyroReadStatus::kNotRunning};
      continue;
    }
    if (status == CanStatus::kTimeout) {
      if (n > 0) return {n, hw::GyroReadStatus::kOk};
      if (clock_.NowNs() < deadline_ns) continue;  // a transport may return early
      counters_.timeouts.fetch_add(1, std::memory_order_relaxed);
      return {0, hw::GyroReadStatus::kTimeout};
    }
    if (status == CanStatus::kBusOff) {
      OnBusOff();
      return {n, hw::GyroReadStatus::kBusOff};
    }
    counters_.bus_errors.fetch_add(1, std::memory_order_relaxed);
    return {n, hw::GyroReadStatus::kError};
  }
}

hw::GyroStatus GyroCanDevice::LastStatus() const noexcept {
  const std::lock_guard lock(status_mutex_);
  return last_status_;
}

hw::GyroCounters GyroCanDevice::Counters() const noexcept {
  const auto get = [](const std::atomic<std::uint64_t>& c) {
    return c.load(std::memory_order_relaxed);
  };
  hw::GyroCounters c;
  c.frames_received = get(counters_.frames_received);
  c.samples_decoded = get(counters_.samples_decoded);
  c.bad_frames = get(counters_.bad_frames);
  c.sequence_gaps = get(counters_.sequence_gaps);
  c.samples_lost = get(counters_.samples_lost);
  c.timeouts = get(counters_.timeouts);
  c.kernel_drops = get(counters_.kernel_drops);
  c.buffer_overruns = get(counters_.buffer_overruns);
  c.command_retries = get(counters_.command_retries);
  c.nacks = get(counters_.nacks);
  c.bus_errors = get(counters_.bus_errors);
  c.unexpected_frames = get(counters_.unexpected_frames);
  c.reference_phases_missing = get(counters_.reference_phases_missing);
  return c;
}

}  // namespace hrgbench::drivers::gyro_can
