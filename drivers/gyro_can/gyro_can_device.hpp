#pragma once
// GyroCanDevice: hw::GyroElectronics over any hw::CanBus, speaking protocol v2 (README.md) to the
// electronics with one node id; other nodes on the same bus are not its business (filtered out).
//
// State machine (State(), hw::GyroMode), changed only by acknowledged commands, status frames and
// bus state:
//   Idle/Configured/Stopped --Configure ack--> Configured --Excite ack--> Exciting
//   Exciting --status ready--> Ready --Release ack--> FreeRun --Stop ack--> Stopped
//   any --bus-off, or electronics report mode Faulted--> Faulted --Stop ack--> Stopped
// A command that times out after every attempt leaves the state unchanged (except Stop: Faulted),
// a rejected one (negative Ack) too.
//
// Commands: each gets a new token; each attempt waits config.ack_timeout_ns for the matching Ack;
// at most config.command_attempts attempts; a retry repeats the token, so the electronics
// re-acknowledge without re-executing. Acks are checked (read-back): the mode they report, and
// for Configure the accepted sample rate.
//
// Receive path (ReadSamples and every wait inside the commands): one CanBus::Receive per frame,
// decoded with GyroCodec, samples assembled into a ring allocated in Create() — no allocation, no
// exception. Every frame is accounted for in one counter (hw::GyroCounters).
//
// Threads: owned by one thread; State(), LastStatus(), Counters() from any thread (atomics; the
// status copy under a mutex held for a 40-byte copy).

#include <atomic>
#include <cstdint>
#include <expected>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyro_can/gyro_codec.hpp"
#include "gyro_can/parameter_block.hpp"
#include "gyro_can/sample_stream_decoder.hpp"
#include "hrgbench/hw/can_bus.hpp"
#include "hrgbench/hw/clock.hpp"
#include "hrgbench/hw/gyro_electronics.hpp"
#include "hrgbench/hw/operating_gyro.hpp"

namespace hrgbench::drivers::gyro_can {

struct GyroCanDeviceConfig {
  // The transport's time base (the Clock a VirtualCanBus was given, SteadyClock for SocketCAN
  // with hardware stamps off): deadlines are measured on it. Not owned; must outlive the device.
  hw::Clock* clock = nullptr;
  // The electronics' node id on the bus (0 … kMaxNodeId): several units may share one bus.
  NodeId node = 0;
  // The electronics answer within 5 ms (README); 50 ms absorbs a loaded bus and host scheduling.
  std::int64_t ack_timeout_ns = 50'000'000;
  // 3 attempts: a single lost frame costs one retry, two in a row are already a sick bus.
  int command_attempts = 3;
  // WaitReady asks for a status this often; the electronics also send it at status_rate_hz.
  std::int64_t status_poll_ns = 20'000'000;
  std::uint8_t status_rate_hz = kDefaultStatusRateHz;
  // Host-side sample buffer: 4096 samples is 4 s at 1 kHz, far more than a capture loop lags.
  std::size_t sample_buffer_capacity = 4096;
  // Ask for the CAN FD sample stream when the transport supports FD.
  bool prefer_fd = false;

  bool IsValid(std::string* why) const;
};

class GyroCanDevice final : public hw::GyroElectronics, public hw::OperatingGyro {
 public:
  // Sets the bus filters to its node's electronics ids and allocates all receive storage.
  // Failure: kInvalidArgument (config), kTransport (filters refused).
  static std::expected<std::unique_ptr<GyroCanDevice>, hw::GyroError> Create(
      hw::CanBus& bus, const GyroCanDeviceConfig& config);

  std::expected<void, hw::GyroError> Configure(const hw::GyroConfig& config) override;
  std::expected<void, hw::GyroError> Excite(const hw::WaveState& target) override;
  std::expected<hw::GyroStatus, hw::GyroError> WaitReady(std::int64_t timeout_ns) override;
  std::expected<std::int64_t, hw::GyroError> Release() override;
  std::expected<void, hw::GyroError> Stop() override;
  std::expected<hw::GyroStatus, hw::GyroError> RequestStatus() override;
  hw::GyroReadResult ReadSamples(std::span<hw::GyroSample> out,
                                 std::int64_t timeout_ns) noexcept override;
  hw::GyroMode State() const noexcept override { return state_.load(std::memory_order_acquire); }
  hw::GyroStatus LastStatus() const noexcept override;
  hw::GyroCounters Counters() const noexcept override;

  // Receives and processes what arrives within `timeout_ns` (status, stale acks, samples into the
  // buffer) and sends nothing: what WaitReady does between two status polls. For a host that keeps
  // LastStatus() current while it does something else, and for replaying recorded traffic
  // (gyro_traffic_replay.hpp). Returns the bus status that ended the wait (kTimeout normally;
  // kBusOff puts the device in kFaulted). Same thread rules as the commands.
  hw::CanStatus ProcessIncoming(std::int64_t timeout_ns) noexcept;

  // The compensation parameter block (parameter_block.hpp, README "Parameter block"), in Idle,
  // Configured or Stopped only (never while a wave is driven or free). ReadParameters: the block
  // the electronics run with. WriteParameters: reads the active block (the outcome's `previous`),
  // stages the new one word by word, reads every staged word back and commits only when all
  // match (kReadBackMismatch otherwise, nothing committed), then reads the committed block back.
  // A timeout during the commit (a power loss) leaves whichever block the electronics' memory
  // then holds: read it. RestorePreviousParameters makes the other slot active again and returns
  // its generation.
  std::expected<ParameterValues, hw::GyroError> ReadParameters() override;
  std::expected<hw::CompensationWrite, hw::GyroError> WriteParameters(
      const ParameterValues& values) override;
  std::expected<std::uint32_t, hw::GyroError> RestorePreviousParameters() override;

  // The operating mode (Configure with whole_angle, then Release: state kOperating): up to
  // out.size() samples of the angle output, waiting at most `timeout_ns` for them; fewer when the
  // wait ends or the stream stops. Lost samples are counted as sequence gaps, a full buffer as an
  // overrun (the oldest sample is dropped). Same thread as the commands.
  std::size_t ReadOperatingSamples(std::span<hw::OperatingSample> out,
                                   std::int64_t timeout_ns) noexcept override;
  // The loops' reports (OperatingLoopsA then B of one sample) since Release: each pair completed
  // in receive order, numbered from its 8-bit seq against the operating samples' numbers (within
  // ±127 samples of the last one received); a half without its partner is counted incomplete.
  hw::OperatingLoopsRecord OperatingLoopsSinceRelease() const noexcept override { return loops_; }

  FrameFormat frame_format() const noexcept { return format_; }
  std::uint32_t sample_rate_hz() const noexcept { return sample_rate_hz_; }

 private:
  GyroCanDevice(hw::CanBus& bus, const GyroCanDeviceConfig& config);

  // Sends the command built by `encode(token)` with bounded retries and returns its Ack.
  template <typename Encode>
  std::expected<Ack, hw::GyroError> Transact(Command command, Encode encode);
  // Receives and processes frames until `done()` or the clock passes `deadline_ns`. Returns the
  // bus status that ended the wait (kOk when done() became true, kTimeout at the deadline).
  template <typename Done>
  hw::CanStatus PumpUntil(std::int64_t deadline_ns, Done done) noexcept;
  std::expected<std::uint32_t, hw::GyroError> ParameterTransact(ParameterOp op, std::uint8_t index,
                                                                std::uint16_t value);
  std::expected<ParameterBlockWords, hw::GyroError> ReadParameterWords(ParameterOp op);
  void OnOperatingSample(const OperatingSampleFrame& frame) noexcept;
  void OnOperatingLoops(const OperatingLoopsHalf& half) noexcept;
  void ProcessFrame(const hw::CanFrame& frame, const hw::ReceiveInfo& info) noexcept;
  void OnBusOff() noexcept;
  void SetState(hw::GyroMode mode) noexcept { state_.store(mode, std::memory_order_release); }
  std::expected<void, hw::GyroError> RequireState(std::span<const hw::GyroMode> allowed,
                                                  const char* what) const;
  void SyncDecoderCounters() noexcept;

  hw::CanBus& bus_;
  GyroCanDeviceConfig config_;
  hw::Clock& clock_;
  SampleStreamDecoder decoder_;
  FrameFormat format_ = FrameFormat::kClassic;
  std::uint32_t sample_rate_hz_ = 0;
  std::uint8_t next_token_ = 0;
  bool streaming_ = false;
  bool whole_angle_ = false;  // the configured run mode

  // The operating mode's samples: a ring allocated at construction.
  std::vector<hw::OperatingSample> operating_buffer_;
  std::size_t operating_head_ = 0;
  std::size_t operating_count_ = 0;
  bool operating_started_ = false;
  std::uint8_t operating_last_seq_ = 0;
  std::uint64_t operating_last_index_ = 0;
  // The loops' reports: the first half waiting for its second, and what completed ones said.
  bool loops_half_pending_ = false;
  OperatingLoopsHalf loops_pending_{};
  hw::OperatingLoopsRecord loops_{};

  // The command being waited for, and what ProcessFrame found.
  bool awaiting_ack_ = false;
  Command awaited_command_ = Command::kStatusRequest;
  std::uint8_t awaited_token_ = 0;
  bool ack_received_ = false;
  Ack ack_{};
  std::int64_t ack_stamp_ns_ = 0;
  std::uint64_t status_frames_ = 0;

  std::atomic<hw::GyroMode> state_{hw::GyroMode::kIdle};
  mutable std::mutex status_mutex_;
  hw::GyroStatus last_status_;

  struct AtomicCounters {
    std::atomic<std::uint64_t> frames_received{0};
    std::atomic<std::uint64_t> bad_frames{0};
    std::atomic<std::uint64_t> timeouts{0};
    std::atomic<std::uint64_t> kernel_drops{0};
    std::atomic<std::uint64_t> command_retries{0};
    std::atomic<std::uint64_t> nacks{0};
    std::atomic<std::uint64_t> bus_errors{0};
    std::atomic<std::uint64_t> unexpected_frames{0};
    std::atomic<std::uint64_t> reference_phases_missing{0};
    // Mirrors of the decoder's counters, published after each frame.
    std::atomic<std::uint64_t> samples_decoded{0};
    std::atomic<std::uint64_t> sequence_gaps{0};
    std::atomic<std::uint64_t> samples_lost{0};
    std::atomic<std::uint64_t> buffer_overruns{0};
  };
  AtomicCounters counters_;
};

}  // namespace hrgbench::drivers::gyro_can
