#include "modbus_rate_table/modbus_rate_table.hpp"

#include <algorithm>
#include <array>
#include <sstream>

#include "modbus_rate_table/modbus_link.hpp"
#include "modbus_rate_table/register_map.hpp"
#include "modbus_rate_table/stable_wait.hpp"

namespace hrgbench::drivers::modbus_rate_table {

namespace {
using hw::RateTableError;
using hw::RateTableErrorCode;

constexpr std::int64_t kNsPerMs = 1'000'000;

std::unexpected<RateTableError> Fail(RateTableErrorCode code, std::string message) {
  return std::unexpected(RateTableError{code, std::move(message)});
}

std::string RegistersText(std::span<const std::uint16_t> regs) {
  std::ostringstream os;
  os << std::hex;
  for (std::size_t i = 0; i < regs.size(); ++i) os << (i ? " " : "") << "0x" << regs[i];
  return os.str();
}

std::array<std::uint16_t, 4> ModeAndRate(hw::RateTableMode mode, double rate_rad_s) {
  const auto rate = EncodeFloat32(static_cast<float>(rate_rad_s));
  return {static_cast<std::uint16_t>(mode), 0, rate[0], rate[1]};
}
}  // namespace

ModbusRateTable::ModbusRateTable(ModbusRateTableConfig config, hw::Clock& clock)
    : config_(std::move(config)), clock_(clock), link_(std::make_unique<ModbusLink>(config_)) {}

ModbusRateTable::~ModbusRateTable() = default;

ModbusTableCounters ModbusRateTable::counters() const noexcept {
  const auto get = [](const std::atomic<std::uint64_t>& c) {
    return c.load(std::memory_order_relaxed);
  };
  return {get(counters_.transactions),      get(counters_.timeouts),
          get(counters_.exception_replies), get(counters_.bad_replies),
          get(counters_.connection_losses), get(counters_.reconnects),
          get(counters_.limit_rejections),  get(counters_.heartbeats)};
}

void ModbusRateTable::Count(const LinkResult& result) noexcept {
  switch (result.status) {
    case LinkStatus::kOk:
      break;
    case LinkStatus::kTimeout:
      ++counters_.timeouts;
      break;
    case LinkStatus::kException:
      ++counters_.exception_replies;
      break;
    case LinkStatus::kBadReply:
      ++counters_.bad_replies;
      break;
    case LinkStatus::kConnectionLost:
      ++counters_.connection_losses;
      break;
  }
}

RateTableError ModbusRateTable::ErrorFrom(const LinkResult& result, const char* what,
                                          int address) const {
  RateTableErrorCode code = RateTableErrorCode::kConnectionLost;
  switch (result.status) {
    case LinkStatus::kOk:  // not an error; callers never pass it
    case LinkStatus::kConnectionLost:
      code = RateTableErrorCode::kConnectionLost;
      break;
    case LinkStatus::kTimeout:
      code = RateTableErrorCode::kTimeout;
      break;
    case LinkStatus::kException:
      code = RateTableErrorCode::kExceptionReply;
      break;
    case LinkStatus::kBadReply:
      code = RateTableErrorCode::kBadReply;
      break;
  }
  std::ostringstream os;
  os << what << " at register " << address << " of " << config_.Describe() << ": "
     << result.Describe();
  return {code, os.str()};
}

std::expected<void, RateTableError> ModbusRateTable::RequireConnected(bool allow_faulted) const {
  return RequireLinkState(state(), allow_faulted, "rate table " + config_.Describe());
}

std::expected<void, RateTableError> ModbusRateTable::Reopen() {
  LinkResult last;
  for (int attempt = 0; attempt < config_.connect_attempts; ++attempt) {
    if (attempt > 0) clock_.SleepForNs(config_.reconnect_backoff_ms * kNsPerMs);
    ++counters_.reconnects;
    last = link_->Open();
    if (last.ok()) return {};
  }
  state_.store(TableLinkState::kDisconnected, std::memory_order_release);
  return std::unexpected(ErrorFrom(last, "reconnect", 0));
}

std::expected<void, RateTableError> ModbusRateTable::Transact(Op op, int address,
                                                              std::span<std::uint16_t> regs) {
  static constexpr const char* kWhat[] = {"read input registers", "read holding registers",
                                          "write holding registers"};
  const char* what = kWhat[static_cast<int>(op)];
  LinkResult result;
  last_exception_code_ = 0;
  for (int attempt = 0; attempt < config_.transaction_attempts; ++attempt) {
    if (!link_->IsOpen()) {
      if (auto reopened = Reopen(); !reopened) return reopened;
    }
    ++counters_.transactions;
    switch (op) {
      case Op::kReadInput:
        result = link_->ReadInputRegisters(address, regs);
        break;
      case Op::kReadHolding:
        result = link_->ReadHoldingRegisters(address, regs);
        break;
      case Op::kWriteHolding:
        result = link_->WriteHoldingRegisters(address, regs);
        break;
    }
    if (result.ok()) return {};
    Count(result);
    // An exception is the table's definite answer: asking again gives the same one.
    if (result.status == LinkStatus::kException) {
      last_exception_code_ = result.exception_code;
      break;
    }
    if (result.status == LinkStatus::kConnectionLost) {
      link_->Close();
    } else {
      link_->Resynchronise();  // a late or garbled reply must not be read as the next one's
    }
  }
  return std::unexpected(ErrorFrom(result, what, address));
}

std::expected<void, RateTableError> ModbusRateTable::WriteAndReadBack(
    int address, std::span<const std::uint16_t> regs) {
  std::array<std::uint16_t, holding::kCount> buffer{};
  auto written = std::span(buffer).first(regs.size());
  std::copy(regs.begin(), regs.end(), written.begin());
  if (auto ok = Transact(Op::kWriteHolding, address, written); !ok) return ok;
  std::array<std::uint16_t, holding::kCount> read_back_buffer{};
  auto read_back = std::span(read_back_buffer).first(regs.size());
  if (auto ok = Transact(Op::kReadHolding, address, read_back); !ok) return ok;
  if (!std::equal(regs.begin(), regs.end(), read_back.begin())) {
    return Fail(RateTableErrorCode::kReadBackMismatch,
                "holding registers from " + std::to_string(address) + ": wrote [" +
                    RegistersText(regs) + "], read back [" + RegistersText(read_back) + "]");
  }
  return {};
}

std::expected<void, RateTableError> ModbusRateTable::WriteHeartbeat() {
  std::array<std::uint16_t, 1> value{static_cast<std::uint16_t>(heartbeat_value_ + 1u)};
  if (auto ok = Transact(Op::kWriteHolding, holding::kHeartbeat, value); !ok) return ok;
  heartbeat_value_ = value[0];
  last_heartbeat_ns_ = clock_.NowNs();
  ++counters_.heartbeats;
  return {};
}

std::expected<void, RateTableError> ModbusRateTable::HeartbeatIfDue() {
  if (clock_.NowNs() - last_heartbeat_ns_ < config_.heartbeat_period_ms * kNsPerMs) return {};
  return WriteHeartbeat();
}

std::expected<void, RateTableError> ModbusRateTable::Connect() {
  std::string why;
  if (!config_.IsValid(&why)) return Fail(RateTableErrorCode::kInvalidConfig, why);
  Disconnect();
  LinkResult opened;
  for (int attempt = 0; attempt < config_.connect_attempts; ++attempt) {
    if (attempt > 0) clock_.SleepForNs(config_.reconnect_backoff_ms * kNsPerMs);
    opened = link_->Open();
    if (opened.ok()) break;
  }
  if (!opened.ok()) {
    return Fail(RateTableErrorCode::kConnectFailed,
                "cannot open " + config_.Describe() + " after " +
                    std::to_string(config_.connect_attempts) + " attempts: " + opened.Describe());
  }
  // The state machine allows transactions from here on; any failure below disconnects again.
  state_.store(TableLinkState::kConnected, std::memory_order_release);
  auto fail = [this](RateTableError error) {
    Disconnect();
    return std::unexpected(std::move(error));
  };
  // The status block is the same in every version, so it is read before the version is known.
  std::array<std::uint16_t, input::kStatusCount> block{};
  if (auto ok = Transact(Op::kReadInput, 0, block); !ok) return fail(ok.error());
  const std::uint16_t version = block[input::kMapVersion];
  if (version < kOldestMapVersion || version > kMapVersion) {
    return fail({RateTableErrorCode::kProtocol,
                 config_.Describe() + " reports register map version " + std::to_string(version) +
                     ", this driver speaks " + std::to_string(kOldestMapVersion) + ".." +
                     std::to_string(kMapVersion)});
  }
  map_version_ = version;
  // Acceleration limit (4-5), heartbeat (6) and watchdog timeout (7) in one write, read back.
  const auto accel = EncodeFloat32(static_cast<float>(config_.accel_limit_rad_s2));
  heartbeat_value_ = static_cast<std::uint16_t>(block[input::kHeartbeatEcho] + 1u);
  const std::array<std::uint16_t, 4> setup{accel[0], accel[1], heartbeat_value_,
                                           static_cast<std::uint16_t>(config_.watchdog_timeout_ms)};
  if (auto ok = WriteAndReadBack(holding::kAccelLimit, setup); !ok) return fail(ok.error());
  last_heartbeat_ns_ = clock_.NowNs();
  const auto status = DecodeStatusBlock(block);
  target_rate_rad_s_ = status.commanded_rate_rad_s;
  if (status.fault) state_.store(TableLinkState::kFaulted, std::memory_order_release);
  return {};
}

std::expected<void, RateTableError> ModbusRateTable::SetRate(double rate_rad_s) {
  if (auto ok = CheckRate(config_.limits, rate_rad_s); !ok) {
    ++counters_.limit_rejections;
    return ok;
  }
  if (auto ok = RequireConnected(/*allow_faulted=*/false); !ok) return ok;
  if (auto ok = HeartbeatIfDue(); !ok) return ok;
  const auto regs = ModeAndRate(hw::RateTableMode::kRate, rate_rad_s);
  if (auto ok = WriteAndReadBack(holding::kMode, regs); !ok) {
    if (ok.error().code == RateTableErrorCode::kExceptionReply &&
        last_exception_code_ == exception_code::kServerDeviceFailure) {
      return RefusedCommand(ok.error(), rate_rad_s);
    }
    return ok;
  }
  target_rate_rad_s_ = static_cast<double>(static_cast<float>(rate_rad_s));
  return {};
}

std::expected<void, RateTableError> ModbusRateTable::RefusedCommand(RateTableError exception,
                                                                    double rate_rad_s) {
  // Exception 04 to a rate command is how the table refuses motion while a fault is latched or
  // the e-stop is pressed; our state was stale (the fault came after the last status). One status
  // read says which fault, and moves the state machine to kFaulted. Without a fault in it (a
  // drive that fails for another reason, or an injected exception) the exception stands as it is.
  const auto status = ReadStatus();
  if (!status || !(status->fault || status->estop)) return std::unexpected(std::move(exception));
  // The first cause is latched: an e-stop pressed after another fault is worth saying too.
  const bool estop_besides =
      status->estop && status->fault_code != static_cast<std::uint16_t>(hw::RateTableFault::kEStop);
  std::ostringstream os;
  os << "rate command " << rate_rad_s << " rad/s refused by " << config_.Describe()
     << " (exception " << exception_code::kServerDeviceFailure << "): the table reports fault '"
     << hw::RateTableFaultName(status->fault_code) << "'"
     << (estop_besides ? " and the e-stop is pressed" : "")
     << "; ResetFault() and read a clean status first";
  return Fail(RateTableErrorCode::kFaulted, os.str());
}

std::expected<void, RateTableError> ModbusRateTable::SetAccelerationLimit(double accel_rad_s2) {
  if (auto ok = CheckAcceleration(config_.limits, accel_rad_s2); !ok) {
    ++counters_.limit_rejections;
    return ok;
  }
  if (auto ok = RequireConnected(/*allow_faulted=*/false); !ok) return ok;
  if (auto ok = HeartbeatIfDue(); !ok) return ok;
  const auto regs = EncodeFloat32(static_cast<float>(accel_rad_s2));
  return WriteAndReadBack(holding::kAccelLimit, regs);
}

std::expected<hw::RateTableStatus, RateTableError> ModbusRateTable::ReadStatus() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return std::unexpected(ok.error());
  if (auto ok = HeartbeatIfDue(); !ok) return std::unexpected(ok.error());
  std::array<std::uint16_t, input::kStatusCount> block{};
  if (auto ok = Transact(Op::kReadInput, 0, block); !ok) return std::unexpected(ok.error());
  hw::RateTableStatus status = DecodeStatusBlock(block);
  status.t_ns = clock_.NowNs();
  // Faulted is entered on any fault bit and left only once a status shows it cleared.
  state_.store(status.fault || status.estop ? TableLinkState::kFaulted : TableLinkState::kConnected,
               std::memory_order_release);
  return status;
}

std::expected<hw::RateTableAngle, RateTableError> ModbusRateTable::ReadAngle() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return std::unexpected(ok.error());
  if (map_version_ < kFirstMapVersionWithAngle) {
    return Fail(RateTableErrorCode::kNotSupported,
                config_.Describe() + " speaks register map version " +
                    std::to_string(map_version_) + ", which has no encoder angle (version " +
                    std::to_string(kFirstMapVersionWithAngle) + " has)");
  }
  // The heartbeat first, so that the read's time window holds this one transaction only.
  if (auto ok = HeartbeatIfDue(); !ok) return std::unexpected(ok.error());
  std::array<std::uint16_t, input::kAngleCount> block{};
  const std::int64_t sent_ns = clock_.NowNs();
  if (auto ok = Transact(Op::kReadInput, input::kAngleFirst, block); !ok)
    return std::unexpected(ok.error());
  const std::int64_t received_ns = clock_.NowNs();
  hw::RateTableAngle angle = DecodeAngleBlock(block);
  if (angle.valid && angle.counts_per_rev == 0) {
    ++counters_.bad_replies;
    return Fail(RateTableErrorCode::kBadReply,
                config_.Describe() + " reports a valid angle with 0 counts per revolution");
  }
  // The table sampled its encoder between our request and its reply: stamp the middle, and keep
  // the window (retries included) for the caller's error budget.
  angle.t_ns = sent_ns + (received_ns - sent_ns) / 2;
  angle.window_ns = received_ns - sent_ns;
  return angle;
}

std::expected<hw::RateTableStatus, RateTableError> ModbusRateTable::WaitUntilStable(
    const hw::StableCriteria& criteria) {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return std::unexpected(ok.error());
  return WaitForStableRate([this] { return ReadStatus(); }, clock_, target_rate_rad_s_, criteria);
}

std::expected<void, RateTableError> ModbusRateTable::Heartbeat() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return ok;
  return WriteHeartbeat();
}

std::expected<void, RateTableError> ModbusRateTable::ResetFault() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return ok;
  if (auto ok = HeartbeatIfDue(); !ok) return ok;
  std::array<std::uint16_t, 1> one{1};
  if (auto ok = Transact(Op::kWriteHolding, holding::kFaultReset, one); !ok) return ok;
  // The state follows the table: the next ReadStatus decides kConnected or still kFaulted.
  if (auto status = ReadStatus(); !status) return std::unexpected(status.error());
  return {};
}

std::expected<void, RateTableError> ModbusRateTable::Stop() {
  if (auto ok = RequireConnected(/*allow_faulted=*/true); !ok) return ok;
  target_rate_rad_s_ = 0.0;
  const auto regs = ModeAndRate(hw::RateTableMode::kIdle, 0.0);
  return WriteAndReadBack(holding::kMode, regs);
}

void ModbusRateTable::SafeStop() noexcept {
  // Mode 0 + rate 0 is accepted by the table in every state, faulted and e-stop included (the map
  // refuses only motion), so this is one write; an exception here means a table off the map.
  try {
    target_rate_rad_s_ = 0.0;
    const std::int64_t deadline_ns = clock_.NowNs() + config_.safe_stop_budget_ms * kNsPerMs;
    auto regs = ModeAndRate(hw::RateTableMode::kIdle, 0.0);
    // Its own loop rather than Transact: one budget for reconnects and retries together, and it
    // works whatever the state machine says (a stop is always worth trying). Every failed attempt
    // (a refused connect, or a connection the peer closes at once) pauses before the next, 10 ms
    // doubling up to reconnect_backoff_ms, and at most kSafeStopAttempts are made: without the
    // pause a table that accepts and closes got 3 131 connections in one budget (issue 25 row 10).
    std::int64_t pause_ns =
        std::min<std::int64_t>(10 * kNsPerMs, config_.reconnect_backoff_ms * kNsPerMs);
    for (int attempt = 1; attempt <= kSafeStopAttempts; ++attempt) {
      if (attempt > 1) {
        const std::int64_t left_ns = deadline_ns - clock_.NowNs();
        if (left_ns <= 0) return;
        clock_.SleepForNs(std::min(pause_ns, left_ns));
        pause_ns = std::min<std::int64_t>(2 * pause_ns, config_.reconnect_backoff_ms * kNsPerMs);
        if (clock_.NowNs() >= deadline_ns) return;
      }
      if (!link_->IsOpen()) {
        ++counters_.reconnects;
        if (!link_->Open().ok()) continue;
      }
      ++counters_.transactions;
      const LinkResult result = link_->WriteHoldingRegisters(holding::kMode, regs);
      if (result.ok()) return;
      Count(result);
      if (result.status == LinkStatus::kException) return;  // the table refuses: retry is futile
      link_->Close();
    }
  } catch (...) {
    // Only std::bad_alloc can get here; nothing more can be done without memory.
  }
}

void ModbusRateTable::Disconnect() noexcept {
  link_->Close();
  state_.store(TableLinkState::kDisconnected, std::memory_order_release);
}

}  // namespace hrgbench::drivers::modbus_rate_table
