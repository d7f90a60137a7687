#pragma once
// GyroSimNode: simulated HRG electronics, a CAN node on any hw::CanBus speaking protocol v2
// as node options.node (its acceptance filter: that node's commands)
// (drivers/gyro_can/README.md): it answers every command with its Ack (re-acknowledging a
// repeated token without re-executing), sends Status at the configured rate, excites to the
// commanded wave state, and in free run streams the y samples of its physics (free_run_source.hpp):
// physics = kSlow, y = (I + C(ξ))·x(t) + σ·n with x(t) the exact closed-form propagation of the
// model from OrbitToState(a, b, θ, φ = 0) at the release instant (slow_model_source.hpp); or
// physics = kCarrier, the 2-DOF resonator at its carrier seen through pick-off channels and
// demodulating electronics (carrier_source.hpp). Ω is read from an injected source at every
// sample and held until the next.
//
// Time: everything runs on the injected Clock. Two ways to drive it:
//   - Service(now) / NextEventNs() (SimulationParticipant): a SimulationClock calls them, so a
//     test runs faster than real time in one thread;
//   - Run(stop): a real-time loop for the hrg-gyro-sim program (SteadyClock, SocketCAN).
// Sample k of a run is due at release + k·1e9/fs ns and is sent when the node is served at or
// after that time.
//
// Failure modes: GyroSimOptions::faults, settable at any time via faults() from the thread that
// drives the node.
//
// Threads: one thread drives the node (Service or Run) and calls every other method; only `stop`
// may be set from another thread.

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "gyro_can/gyro_codec.hpp"
#include "hrgbench/estimator/simulation.hpp"
#include "hrgbench/estimator/whole_angle_control.hpp"
#include "hrgbench/hw/can_bus.hpp"
#include "hrgbench/hw/clock.hpp"
#include "sim/free_run_source.hpp"
#include "sim/gyro_sim_options.hpp"
#include "sim/operating_plant.hpp"
#include "sim/simulation_clock.hpp"

namespace hrgbench::drivers::sim {

// Ω about the sensitive axis in rad/s (rate table + Earth-rate component), read at every sample.
using OmegaSource = std::function<double()>;

struct GyroSimStatistics {
  std::uint64_t commands = 0;    // valid commands received
  std::uint64_t bad_frames = 0;  // command-id frames that failed to decode
  std::uint64_t samples = 0;     // samples generated (sent or not)
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_dropped = 0;    // by the drop failure mode
  std::uint64_t frames_corrupted = 0;  // by the corrupt failure mode
  std::uint64_t send_failures = 0;     // Send() did not return kOk
  std::uint64_t runs = 0;              // releases
  std::uint64_t power_losses = 0;      // by the power-loss-on-commit failure mode
};

class GyroSimNode final : public SimulationParticipant {
 public:
  // `bus`, `clock` must outlive the node. `short_bus` (optional) is called once by the bus-off
  // failure mode: in-process it takes every node off the bus (VirtualCanBus::SetBusOff); a real
  // adapter cannot do that from software, so the program leaves it empty.
  GyroSimNode(hw::CanBus& bus, const hw::Clock& clock, const GyroSimOptions& options,
              OmegaSource omega, std::function<void()> short_bus = {});

  std::int64_t NextEventNs() const noexcept override;
  bool Service(std::int64_t now_ns) noexcept override;  // true when it sent a frame
  // Real-time loop until `stop` becomes true: waits in Receive until the next event.
  void Run(const std::atomic<bool>& stop) noexcept;

  GyroSimFaults& faults() noexcept { return options_.faults; }
  hw::GyroMode mode() const noexcept { return mode_; }
  GyroSimStatistics Statistics() const noexcept { return statistics_; }
  // The wave state commanded by the last Excite (quantised as on the wire).
  estimator::Orbit commanded_orbit() const noexcept { return orbit_; }
  // The physics behind the samples (for tests and diagnostics).
  const FreeRunSource& source() const noexcept { return *source_; }
  // The compensation parameter block the electronics would boot with now (the newest valid slot
  // of their non-volatile memory) and its generation; nullopt when no slot is valid.
  std::optional<gyro_can::ParameterValues> ActiveParameters() const noexcept;
  std::uint32_t ActiveParameterGeneration() const noexcept;

 private:
  void HandleFrame(const hw::CanFrame& frame, std::int64_t now_ns) noexcept;
  void Execute(gyro_can::Command command, std::uint8_t token, const hw::CanFrame& frame,
               std::int64_t now_ns) noexcept;
  void Advance(std::int64_t now_ns) noexcept;
  // A Parameter command in a mode that allows it; false when power was lost (no Ack, restarted).
  bool ExecuteParameter(const gyro_can::ParameterCommand& command, gyro_can::Ack* ack) noexcept;
  void SelectActiveParameterSlot() noexcept;  // at power-on: the newest slot whose CRC holds
  void EmitSample(std::int64_t t_ns) noexcept;
  void EmitOperatingSample() noexcept;  // the operating mode's next sample
  bool StartOperating() noexcept;       // false when no valid parameter block is active
  void SendSampleFrame(hw::CanFrame frame) noexcept;
  void SendStatus() noexcept;
  void Send(const hw::CanFrame& frame) noexcept;
  std::int64_t NextTimedEventNs() const noexcept;  // samples and status, without the poll tick
  std::int64_t SampleDueNs(std::uint64_t k) const noexcept;
  // The stream has stopped at the fault's sample in this run.
  bool Stalled(const GyroSimFaults& faults) const noexcept;
  std::int64_t StatusPeriodNs() const noexcept;
  double TemperatureC() const noexcept;  // housing temperature now

  hw::CanBus& bus_;
  const hw::Clock& clock_;
  GyroSimOptions options_;
  OmegaSource omega_;
  std::function<void()> short_bus_;
  std::unique_ptr<FreeRunSource> source_;
  std::int64_t power_on_ns_ = 0;  // temperature drift counts from here

  hw::GyroMode mode_ = hw::GyroMode::kIdle;
  std::uint8_t fault_bits_ = 0;
  std::uint16_t sample_rate_hz_ = 0;
  gyro_can::FrameFormat format_ = gyro_can::FrameFormat::kClassic;
  std::uint8_t status_rate_hz_ = gyro_can::kDefaultStatusRateHz;
  estimator::Orbit orbit_;
  std::int64_t excite_done_ns_ = 0;

  // Operating mode (Configure's run mode): the resonator with the control in it, run by the
  // whole-angle loops with the active parameter block (operating_plant.hpp: either physics).
  gyro_can::RunMode run_mode_ = gyro_can::RunMode::kFreeRun;
  std::unique_ptr<OperatingPlant> plant_;
  std::unique_ptr<estimator::WholeAngleControl> control_;
  Eigen::Vector4d command_ = Eigen::Vector4d::Zero();
  double angle_output_rad_ = 0.0;
  double operating_period_s_ = 1e-3;  // the loops' step, the sample period set at the release
  double energy_setpoint_ = 0.0;      // S*, the loops' reports give Ŝ relative to it

  // Free run.
  std::int64_t release_ns_ = 0;
  std::uint64_t next_sample_ = 0;
  gyro_can::SampleFdBlock fd_block_;
  std::uint64_t sample_frames_ = 0;  // sample frames produced this run (for drop_every_nth)

  // Retry detection: the last command and its Ack.
  bool have_last_ = false;
  gyro_can::Command last_command_ = gyro_can::Command::kStatusRequest;
  std::uint8_t last_token_ = 0;
  gyro_can::Ack last_ack_;

  // Non-volatile memory: two slots, written alternately, the newest valid one active (a commit
  // that loses power tears only the slot being written); and the staging block in RAM.
  struct ParameterSlot {
    bool written = false;
    std::uint32_t generation = 0;
    gyro_can::ParameterBlockWords words{};
  };
  std::array<ParameterSlot, 2> parameter_slots_{};
  int active_slot_ = -1;
  gyro_can::ParameterBlockWords staging_{};
  bool staging_open_ = false;

  std::int64_t next_status_ns_ = 0;
  std::int64_t next_poll_ns_ = 0;
  bool bus_shorted_ = false;
  GyroSimStatistics statistics_;
};

}  // namespace hrgbench::drivers::sim
