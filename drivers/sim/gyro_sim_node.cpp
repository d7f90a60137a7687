#include "sim/gyro_sim_node.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
#include <numbers>

#include "sim/carrier_source.hpp"
#include "sim/slow_model_source.hpp"

namespace hrgbench::drivers::sim {
namespace {

using gyro_can::Ack;
using gyro_can::AckResult;
using gyro_can::Command;
using gyro_can::FrameFormat;
using hw::GyroMode;

constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();

std::unique_ptr<FreeRunSource> MakeSource(const GyroSimOptions& o) {
  if (o.physics == GyroPhysics::kCarrier) return std::make_unique<CarrierSource>(o.carrier, o.seed);
  return std::make_unique<SlowModelSource>(o.delta, o.xi, o.sigma, o.seed, o.resonant_frequency_hz);
}

}  // namespace

GyroSimNode::GyroSimNode(hw::CanBus& bus, const hw::Clock& clock, const GyroSimOptions& options,
                         OmegaSource omega, std::function<void()> short_bus)
    : bus_(bus),
      clock_(clock),
      options_(options),
      omega_(std::move(omega)),
      short_bus_(std::move(short_bus)),
      source_(MakeSource(options)) {
  // The electronics' acceptance filter: their node's commands (Stop 0x02n, Parameter 0x03n; the
  // others 0x04n … 0x07n). HandleFrame checks the node too, for a transport that cannot filter.
  static_assert(gyro_can::can_id::kStatusRequest == (gyro_can::can_id::kConfigure | 0x030));
  const std::array<hw::CanFilter, 3> commands = {
      hw::CanFilter{gyro_can::NodeMessageId(gyro_can::can_id::kStop, options_.node), 0x7FF, false},
      hw::CanFilter{gyro_can::NodeMessageId(gyro_can::can_id::kParameter, options_.node), 0x7FF,
                    false},
      hw::CanFilter{gyro_can::NodeMessageId(gyro_can::can_id::kConfigure, options_.node), 0x7CF,
                    false}};
  (void)bus_.SetFilters(commands);
  // Out of the factory: the design's compensation in slot 0.
  parameter_slots_[0] = {true, 1, gyro_can::EncodeParameterBlock(options_.factory_parameters)};
  active_slot_ = 0;
  const std::int64_t now = clock_.NowNs();
  power_on_ns_ = now;
  next_poll_ns_ = now;
  next_status_ns_ = now;
}

std::int64_t GyroSimNode::SampleDueNs(std::uint64_t k) const noexcept {
  return release_ns_ + static_cast<std::int64_t>(k * 1'000'000'000ull /
                                                 std::max<std::uint16_t>(sample_rate_hz_, 1));
}

bool GyroSimNode::Stalled(const GyroSimFaults& faults) const noexcept {
  // statistics_.runs counts the releases so far, this run's included.
  return faults.stall_after_samples >= 0 && statistics_.runs >= faults.stall_from_run &&
         next_sample_ >= static_cast<std::uint64_t>(faults.stall_after_samples);
}

std::int64_t GyroSimNode::StatusPeriodNs() const noexcept {
  return status_rate_hz_ == 0 ? kNever : 1'000'000'000 / status_rate_hz_;
}

std::int64_t GyroSimNode::NextTimedEventNs() const noexcept {
  std::int64_t next = status_rate_hz_ == 0 ? kNever : next_status_ns_;
  const bool stalled = Stalled(options_.faults);
  if ((mode_ == GyroMode::kFreeRun || mode_ == GyroMode::kOperating) && !stalled) {
    next = std::min(next, SampleDueNs(next_sample_));
  }
  if (mode_ == GyroMode::kExciting && !options_.faults.never_ready) {
    next = std::min(next, excite_done_ns_);
  }
  return next;
}

std::int64_t GyroSimNode::NextEventNs() const noexcept {
  return std::min(next_poll_ns_, NextTimedEventNs());
}

bool GyroSimNode::Service(std::int64_t now_ns) noexcept {
  const std::uint64_t sent_before = statistics_.frames_sent + statistics_.send_failures;
  hw::CanFrame frame;
  while (bus_.Receive(&frame, 0, nullptr) == hw::CanStatus::kOk) HandleFrame(frame, now_ns);
  Advance(now_ns);
  next_poll_ns_ = now_ns + options_.poll_period_ns;
  return statistics_.frames_sent + statistics_.send_failures != sent_before;
}

void GyroSimNode::Run(const std::atomic<bool>& stop) noexcept {
  hw::CanFrame frame;
  while (!stop.load(std::memory_order_acquire)) {
    Advance(clock_.NowNs());
    // Frames wake Receive at once; otherwise wait for the next sample or status, at most 50 ms so
    // `stop` is seen promptly.
    const std::int64_t now = clock_.NowNs();
    const std::int64_t wait_ns = std::clamp<std::int64_t>(NextTimedEventNs() - now, 0, 50'000'000);
    if (bus_.Receive(&frame, wait_ns, nullptr) == hw::CanStatus::kOk) {
      HandleFrame(frame, clock_.NowNs());
    }
  }
}

void GyroSimNode::Send(const hw::CanFrame& frame) noexcept {
  const hw::CanStatus status = bus_.Send(frame, 0);
  if (status == hw::CanStatus::kOk) {
    ++statistics_.frames_sent;
    return;
  }
  ++statistics_.send_failures;
  // The transmit queue is full (the bus is overloaded): the frame is lost at the source, and the
  // status says so until Stop (fault bit 4; the host also sees the gap in the sample numbers).
  if (status == hw::CanStatus::kBufferFull) fault_bits_ |= hw::gyro_fault::kSampleOverrun;
}

void GyroSimNode::HandleFrame(const hw::CanFrame& frame, std::int64_t now_ns) noexcept {
  if (frame.extended || !gyro_can::IsCommandId(frame.id) ||
      gyro_can::NodeOf(frame.id) != options_.node) {
    return;  // not addressed to us
  }
  const std::uint32_t message = gyro_can::MessageOf(frame.id);
  Command command = Command::kStatusRequest;
  std::uint8_t token = 0;
  gyro_can::DecodeStatus status = gyro_can::DecodeStatus::kWrongId;
  if (message == gyro_can::can_id::kConfigure) {
    gyro_can::ConfigureCommand c;
    status = gyro_can::DecodeConfigure(frame, options_.node, &c);
    command = Command::kConfigure;
    token = c.token;
  } else if (message == gyro_can::can_id::kExcite) {
    gyro_can::ExciteCommand c;
    status = gyro_can::DecodeExcite(frame, options_.node, &c);
    command = Command::kExcite;
    token = c.token;
  } else if (message == gyro_can::can_id::kParameter) {
    gyro_can::ParameterCommand c;
    status = gyro_can::DecodeParameter(frame, options_.node, &c);
    command = Command::kParameter;
    token = c.token;
  } else {
    gyro_can::SimpleCommand c;
    status = gyro_can::DecodeSimpleCommand(frame, options_.node, &c);
    command = c.command;
    token = c.token;
  }
  if (status != gyro_can::DecodeStatus::kOk) {
    ++statistics_.bad_frames;  // a real node ignores it; the host's retry recovers
    return;
  }
  ++statistics_.commands;
  if (options_.faults.no_reply) return;
  if (options_.faults.ignore_commands > 0) {
    --options_.faults.ignore_commands;
    return;
  }
  if (have_last_ && command == last_command_ && token == last_token_) {
    // A retry: the Ack was lost. Answer again, do not execute again.
    Ack ack = last_ack_;
    if (command == Command::kRelease && ack.result == AckResult::kOk) {
      ack.arg = static_cast<std::uint32_t>((now_ns - release_ns_) / 1000);
    }
    Send(gyro_can::EncodeAck(options_.node, ack));
    if (command == Command::kStatusRequest) SendStatus();
    return;
  }
  Execute(command, token, frame, now_ns);
}

void GyroSimNode::Execute(Command command, std::uint8_t token, const hw::CanFrame& frame,
                          std::int64_t now_ns) noexcept {
  Ack ack{command, token, AckResult::kOk, mode_, 0};
  const bool faulted = mode_ == GyroMode::kFaulted;
  switch (command) {
    case Command::kConfigure: {
      gyro_can::ConfigureCommand c;
      gyro_can::DecodeConfigure(frame, options_.node, &c);
      const bool fd_ok = options_.supports_fd && bus_.SupportsFd();
      const std::uint16_t max_rate = c.format == FrameFormat::kFd
                                         ? gyro_can::kMaxFdSampleRateHz
                                         : gyro_can::kMaxClassicSampleRateHz;
      if (faulted) {
        ack.result = AckResult::kFaulted;
      } else if (mode_ != GyroMode::kIdle && mode_ != GyroMode::kConfigured &&
                 mode_ != GyroMode::kStopped) {
        ack.result = AckResult::kBadState;
      } else if (c.sample_rate_hz < 1 || c.sample_rate_hz > max_rate ||
                 (c.format == FrameFormat::kFd && !fd_ok)) {
        ack.result = AckResult::kBadArgument;
      } else {
        sample_rate_hz_ = c.sample_rate_hz;
        run_mode_ = c.run_mode;
        format_ = c.format;
        status_rate_hz_ = c.status_rate_hz;
        next_status_ns_ = now_ns;
        mode_ = GyroMode::kConfigured;
        ack.arg = c.sample_rate_hz;
      }
      break;
    }
    case Command::kExcite: {
      gyro_can::ExciteCommand c;
      gyro_can::DecodeExcite(frame, options_.node, &c);
      if (faulted) {
        ack.result = AckResult::kFaulted;
      } else if (mode_ != GyroMode::kConfigured && mode_ != GyroMode::kReady) {
        ack.result = AckResult::kBadState;
      } else if (c.a_raw == 0 || std::abs(static_cast<int>(c.b_raw)) >= c.a_raw) {
        ack.result = AckResult::kBadArgument;
      } else {
        orbit_ = {c.a_raw * gyro_can::kExciteLsb, c.b_raw * gyro_can::kExciteLsb,
                  c.theta_raw * gyro_can::kExciteLsb, 0.0};
        mode_ = GyroMode::kExciting;
        excite_done_ns_ = now_ns + static_cast<std::int64_t>(options_.excite_time_s * 1e9);
      }
      break;
    }
    case Command::kRelease:
      if (faulted) {
        ack.result = AckResult::kFaulted;
      } else if (mode_ != GyroMode::kReady) {
        ack.result = AckResult::kBadState;
      } else if (run_mode_ == gyro_can::RunMode::kWholeAngle) {
        release_ns_ = now_ns;
        next_sample_ = 0;
        sample_frames_ = 0;
        if (StartOperating()) {
          mode_ = GyroMode::kOperating;
          ++statistics_.runs;
        } else {
          ack.result = AckResult::kBadState;  // no valid compensation to run with
        }
      } else {
        // The release instant is now: sample 0 is x0 itself, sent right after this Ack.
        mode_ = GyroMode::kFreeRun;
        release_ns_ = now_ns;
        next_sample_ = 0;
        sample_frames_ = 0;
        fd_block_ = {};
        source_->Release({orbit_, omega_ ? omega_() : 0.0, static_cast<double>(sample_rate_hz_),
                          statistics_.runs, TemperatureC(), options_.temperature_drift_c_per_s});
        ++statistics_.runs;
      }
      break;
    case Command::kStop:
      mode_ = GyroMode::kStopped;
      fault_bits_ = 0;
      break;
    case Command::kStatusRequest:
      break;
    case Command::kParameter: {
      gyro_can::ParameterCommand c;
      gyro_can::DecodeParameter(frame, options_.node, &c);
      if (faulted) {
        ack.result = AckResult::kFaulted;
      } else if (mode_ != GyroMode::kIdle && mode_ != GyroMode::kConfigured &&
                 mode_ != GyroMode::kStopped) {
        ack.result = AckResult::kBadState;  // never while a wave is driven or free
      } else if (!ExecuteParameter(c, &ack)) {
        return;  // power lost: no Ack, the electronics restart
      }
      break;
    }
  }
  ack.mode = mode_;
  last_ack_ = ack;
  last_command_ = command;
  last_token_ = token;
  have_last_ = true;
  Send(gyro_can::EncodeAck(options_.node, ack));
  if (command == Command::kStatusRequest) SendStatus();
  Advance(now_ns);
}

bool GyroSimNode::ExecuteParameter(const gyro_can::ParameterCommand& c,
                                   gyro_can::Ack* ack) noexcept {
  using gyro_can::ParameterOp;
  const bool index_ok = c.index < gyro_can::kParameterBlockWords;
  const auto word = [](std::uint8_t index, std::uint16_t value) {
    return (static_cast<std::uint32_t>(index) << 16) | value;
  };
  switch (c.op) {
    case ParameterOp::kBegin:
      if (c.value != gyro_can::kParameterBlockWords) {
        ack->result = AckResult::kBadArgument;
      } else {
        staging_ = {};
        staging_open_ = true;
        ack->arg = c.value;
      }
      break;
    case ParameterOp::kWrite:
      if (!staging_open_) {
        ack->result = AckResult::kBadState;
      } else if (!index_ok) {
        ack->result = AckResult::kBadArgument;
      } else {
        const bool corrupt = options_.faults.corrupt_parameter_word == c.index;
        staging_[c.index] = corrupt ? static_cast<std::uint16_t>(c.value ^ 1u) : c.value;
        ack->arg = word(c.index, c.value);
      }
      break;
    case ParameterOp::kReadStaged:
      if (!staging_open_) {
        ack->result = AckResult::kBadState;
      } else if (!index_ok) {
        ack->result = AckResult::kBadArgument;
      } else {
        ack->arg = word(c.index, staging_[c.index]);
      }
      break;
    case ParameterOp::kReadActive:
      if (active_slot_ < 0) {
        ack->result = AckResult::kBadState;
      } else if (!index_ok) {
        ack->result = AckResult::kBadArgument;
      } else {
        ack->arg =
            word(c.index, parameter_slots_[static_cast<std::size_t>(active_slot_)].words[c.index]);
      }
      break;
    case ParameterOp::kCommit: {
      if (!staging_open_) {
        ack->result = AckResult::kBadState;
        break;
      }
      if (gyro_can::DecodeParameterBlock(staging_, nullptr) !=
          gyro_can::ParameterBlockStatus::kOk) {
        ack->result = AckResult::kBadArgument;  // refused: nothing written
        break;
      }
      const std::size_t target = active_slot_ == 0 ? 1 : 0;
      const std::uint32_t generation =
          active_slot_ < 0
              ? 1
              : parameter_slots_[static_cast<std::size_t>(active_slot_)].generation + 1;
      ParameterSlot& slot = parameter_slots_[target];
      slot.written = true;
      slot.generation = generation;
      if (options_.faults.power_loss_on_commit > 0) {
        --options_.faults.power_loss_on_commit;
        // Power fails with half of the slot written over the older block it held: the slot's CRC
        // no longer holds, so at power-on the other slot (the block before) is the active one.
        for (std::size_t i = 0; i < staging_.size() / 2; ++i) slot.words[i] = staging_[i];
        slot.words.back() = static_cast<std::uint16_t>(~staging_.back());
        ++statistics_.power_losses;
        mode_ = GyroMode::kIdle;
        fault_bits_ = 0;
        staging_open_ = false;
        have_last_ = false;
        SelectActiveParameterSlot();
        return false;
      }
      slot.words = staging_;
      active_slot_ = static_cast<int>(target);
      staging_open_ = false;
      ack->arg = generation;
      break;
    }
    case ParameterOp::kRestore: {
      const std::size_t other = active_slot_ == 0 ? 1 : 0;
      const ParameterSlot& slot = parameter_slots_[other];
      if (active_slot_ < 0 || !slot.written ||
          gyro_can::DecodeParameterBlock(slot.words, nullptr) !=
              gyro_can::ParameterBlockStatus::kOk) {
        ack->result = AckResult::kBadArgument;  // no valid block to go back to
      } else {
        active_slot_ = static_cast<int>(other);
        ack->arg = slot.generation;
      }
      break;
    }
  }
  return true;
}

void GyroSimNode::SelectActiveParameterSlot() noexcept {
  active_slot_ = -1;
  for (std::size_t i = 0; i < parameter_slots_.size(); ++i) {
    const ParameterSlot& slot = parameter_slots_[i];
    if (!slot.written || gyro_can::DecodeParameterBlock(slot.words, nullptr) !=
                             gyro_can::ParameterBlockStatus::kOk) {
      continue;
    }
    if (active_slot_ < 0 ||
        slot.generation > parameter_slots_[static_cast<std::size_t>(active_slot_)].generation) {
      active_slot_ = static_cast<int>(i);
    }
  }
}

std::optional<gyro_can::ParameterValues> GyroSimNode::ActiveParameters() const noexcept {
  if (active_slot_ < 0) return std::nullopt;
  gyro_can::ParameterValues values{};
  if (gyro_can::DecodeParameterBlock(parameter_slots_[static_cast<std::size_t>(active_slot_)].words,
                                     &values) != gyro_can::ParameterBlockStatus::kOk) {
    return std::nullopt;
  }
  return values;
}

std::uint32_t GyroSimNode::ActiveParameterGeneration() const noexcept {
  return active_slot_ < 0 ? 0 : parameter_slots_[static_cast<std::size_t>(active_slot_)].generation;
}

void GyroSimNode::Advance(std::int64_t now_ns) noexcept {
  GyroSimFaults& faults = options_.faults;
  if (faults.fault_bits != 0) {  // one-shot injection, latched until Stop
    fault_bits_ |= faults.fault_bits;
    faults.fault_bits = 0;
    mode_ = GyroMode::kFaulted;
  }
  if (mode_ == GyroMode::kExciting && now_ns >= excite_done_ns_ && !faults.never_ready) {
    mode_ = GyroMode::kReady;
  }
  while ((mode_ == GyroMode::kFreeRun || mode_ == GyroMode::kOperating) &&
         SampleDueNs(next_sample_) <= now_ns) {
    if (Stalled(faults)) break;
    if (faults.bus_off_after_samples >= 0 && !bus_shorted_ &&
        next_sample_ >= static_cast<std::uint64_t>(faults.bus_off_after_samples)) {
      bus_shorted_ = true;
      if (short_bus_) short_bus_();
    }
    if (mode_ == GyroMode::kOperating) {
      EmitOperatingSample();
    } else {
      EmitSample(SampleDueNs(next_sample_));
    }
  }
  if (status_rate_hz_ != 0 && now_ns >= next_status_ns_) {
    SendStatus();
    next_status_ns_ = now_ns + StatusPeriodNs();
  }
}

void GyroSimNode::EmitSample(std::int64_t t_ns) noexcept {
  const double omega = omega_ ? omega_() : 0.0;
  const estimator::Observation y = source_->Sample(next_sample_, t_ns - release_ns_, omega);
  std::int32_t raw[4];
  for (int c = 0; c < 4; ++c) raw[c] = gyro_can::QuantiseY(y(c));
  const std::uint64_t k = next_sample_++;
  ++statistics_.samples;
  // The reference phase of every 5th sample, before that sample's frames (not a sample frame:
  // the sample-frame fault injections leave it alone).
  if (k % gyro_can::kReferencePhaseInterval == 0) {
    const double chi_rad = source_->ReportedReferencePhaseRad();
    if (!std::isnan(chi_rad)) {
      Send(gyro_can::EncodeReferencePhase(
          options_.node,
          {static_cast<std::uint16_t>(k & 0xFFFFu), gyro_can::QuantiseReferencePhase(chi_rad)}));
    }
  }
  if (format_ == FrameFormat::kClassic) {
    const auto seq = static_cast<std::uint8_t>(k & 0xFFu);
    SendSampleFrame(gyro_can::EncodeSampleHalf(options_.node, {0, seq, {raw[0], raw[1]}}));
    SendSampleFrame(gyro_can::EncodeSampleHalf(options_.node, {1, seq, {raw[2], raw[3]}}));
    return;
  }
  if (fd_block_.count == 0) fd_block_.seq = static_cast<std::uint16_t>(k & 0xFFFFu);
  fd_block_.y_raw[fd_block_.count] = {raw[0], raw[1], raw[2], raw[3]};
  if (++fd_block_.count == gyro_can::kSamplesPerFdFrame) {
    SendSampleFrame(gyro_can::EncodeSampleFd(options_.node, fd_block_));
    fd_block_ = {};
  }
}

bool GyroSimNode::StartOperating() noexcept {
  const std::optional<gyro_can::ParameterValues> values = ActiveParameters();
  if (!values) return false;
  const estimator::CompensationSet p = estimator::CompensationFromVector(
      Eigen::Map<const estimator::CompensationVector>(values->data()));
  if (p.delta[estimator::kScaleFactor] == 0.0) return false;
  const double h = 1.0 / std::max<std::uint16_t>(sample_rate_hz_, 1);
  operating_period_s_ = h;
  plant_ = MakeOperatingPlant(options_,
                              {orbit_, omega_ ? omega_() : 0.0, h, options_.seed + statistics_.runs,
                               TemperatureC(), options_.temperature_drift_c_per_s});
  estimator::WholeAngleLoopGains gains;
  gains.energy_setpoint = orbit_.a * orbit_.a + orbit_.b * orbit_.b;
  energy_setpoint_ = gains.energy_setpoint;
  gains.measurement_delay_s = plant_->measurement_delay_s();
  control_ = std::make_unique<estimator::WholeAngleControl>(p, gains, h);
  command_.setZero();
  angle_output_rad_ = 0.0;
  return true;
}

void GyroSimNode::EmitOperatingSample() noexcept {
  const double h = operating_period_s_;
  const estimator::WholeAngleSample s =
      control_->Step(plant_->Observe(omega_ ? omega_() : 0.0, command_));
  command_ = s.u;
  plant_->Advance(command_);
  if (std::isfinite(s.rate_rad_s)) angle_output_rad_ += s.rate_rad_s * h;
  const std::uint64_t k = next_sample_++;
  ++statistics_.samples;
  // The angle output wraps at ±1024 rad on the wire (int32 of 2^-21 rad), the wave angle at π.
  const double turns = std::floor(angle_output_rad_ / 2048.0 + 0.5);
  const auto output_raw = static_cast<std::int64_t>(
      std::llround((angle_output_rad_ - 2048.0 * turns) / gyro_can::kAngleOutputLsbRad));
  const double wave =
      std::fmod(std::fmod(s.angle_rad, std::numbers::pi) + std::numbers::pi, std::numbers::pi);
  const auto wave_raw = static_cast<std::uint32_t>(std::llround(wave / gyro_can::kWaveAngleLsbRad));
  SendSampleFrame(gyro_can::EncodeOperatingSample(
      options_.node,
      {static_cast<std::uint8_t>(k & 0xFFu),
       static_cast<std::int32_t>(std::clamp<std::int64_t>(output_raw, INT32_MIN, INT32_MAX)),
       static_cast<std::uint16_t>(wave_raw & 0xFFFFu)}));
  // The loops' state of every 10th sample, after that sample's angle (not sample frames: the
  // sample-frame fault injections leave them alone, as they do the reference phase).
  if (k % gyro_can::kOperatingLoopsInterval == 0) {
    const auto seq = static_cast<std::uint8_t>(k & 0xFFu);
    const double setpoint = energy_setpoint_;
    const double energy_error = setpoint > 0.0 ? (s.energy - setpoint) / setpoint : 0.0;
    const double ratio = s.energy > 0.0 ? s.quadrature / s.energy : 0.0;
    Send(gyro_can::EncodeOperatingLoopsHalf(
        options_.node, {0,
                        seq,
                        {gyro_can::QuantiseLoopValue(energy_error, gyro_can::kEnergyErrorLsb),
                         gyro_can::QuantiseLoopValue(ratio, gyro_can::kQuadratureRatioLsb)}}));
    Send(gyro_can::EncodeOperatingLoopsHalf(
        options_.node,
        {1,
         seq,
         {gyro_can::QuantiseLoopValue(s.amplitude_effort_per_s, gyro_can::kLoopEffortLsb),
          gyro_can::QuantiseLoopValue(s.quadrature_effort_rad_s, gyro_can::kLoopEffortLsb)}}));
  }
}

void GyroSimNode::SendSampleFrame(hw::CanFrame frame) noexcept {
  GyroSimFaults& faults = options_.faults;
  ++sample_frames_;
  if (faults.drop_sample_frames > 0 ||
      (faults.drop_every_nth_frame > 0 && sample_frames_ % faults.drop_every_nth_frame == 0)) {
    if (faults.drop_sample_frames > 0) --faults.drop_sample_frames;
    ++statistics_.frames_dropped;
    return;
  }
  if (faults.corrupt_sample_frames > 0) {
    --faults.corrupt_sample_frames;
    frame.data[1] ^= 0x01;  // after the CRC: the host's CRC check must catch it
    ++statistics_.frames_corrupted;
  }
  Send(frame);
}

double GyroSimNode::TemperatureC() const noexcept {
  const double since_power_on_s = static_cast<double>(clock_.NowNs() - power_on_ns_) * 1e-9;
  return std::clamp(options_.temperature_c + options_.temperature_drift_c_per_s * since_power_on_s,
                    -327.67, 327.67);
}

void GyroSimNode::SendStatus() noexcept {
  gyro_can::StatusMessage status;
  status.mode = mode_;
  status.fault_bits = fault_bits_;
  status.pll_lock =
      (mode_ == GyroMode::kExciting || mode_ == GyroMode::kReady || mode_ == GyroMode::kFreeRun) &&
      (fault_bits_ & hw::gyro_fault::kPllUnlock) == 0;
  status.ready = mode_ == GyroMode::kReady;
  const double temperature_c = TemperatureC();
  status.frequency_mhz = static_cast<std::uint32_t>(std::clamp(
      std::lround(source_->ReportedFrequencyHz(temperature_c) * 1e3), 0l, (1l << 24) - 1));
  status.temperature_centi_c = static_cast<std::int16_t>(std::lround(temperature_c * 100));
  Send(gyro_can::EncodeStatus(options_.node, status));
}

}  // namespace hrgbench::drivers::sim
