#include "sim/modbus_table_server.hpp"

#include <modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>

#include "modbus_rate_table/register_map.hpp"

namespace hrgbench::drivers::sim {

namespace {
namespace holding = modbus_rate_table::holding;
namespace input = modbus_rate_table::input;

constexpr std::uint8_t kFnReadHolding = 0x03;
constexpr std::uint8_t kFnReadInput = 0x04;
constexpr std::uint8_t kFnWriteSingle = 0x06;
constexpr std::uint8_t kFnWriteMultiple = 0x10;
constexpr std::uint8_t kFnMaskWrite = 0x16;
constexpr std::uint8_t kFnWriteAndRead = 0x17;

// The register map's exception numbers are the protocol's, which libmodbus names.
static_assert(modbus_rate_table::exception_code::kIllegalFunction ==
              MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
static_assert(modbus_rate_table::exception_code::kIllegalDataAddress ==
              MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
static_assert(modbus_rate_table::exception_code::kIllegalDataValue ==
              MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
static_assert(modbus_rate_table::exception_code::kServerDeviceFailure ==
              MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE);

// Big-endian 16-bit field of a Modbus PDU (libmodbus' macros trip -Wconversion).
int GetU16(const std::uint8_t* bytes, int index) { return (bytes[index] << 8) | bytes[index + 1]; }
void SetU16(std::uint8_t* bytes, int index, int value) {
  bytes[index] = static_cast<std::uint8_t>((value >> 8) & 0xFF);
  bytes[index + 1] = static_cast<std::uint8_t>(value & 0xFF);
}
std::string ErrnoText(const char* what) {
  return std::string(what) + ": " + modbus_strerror(errno);
}
}  // namespace

ModbusTableServer::ModbusTableServer(TablePhysics& physics, TableServerOptions options)
    : physics_(physics), options_(std::move(options)) {}

ModbusTableServer::~ModbusTableServer() { CloseAll(); }

std::expected<void, std::string> ModbusTableServer::Open() {
  CloseAll();
  const bool tcp = options_.transport == TableServerOptions::Transport::kTcp;
  ctx_ = tcp ? modbus_new_tcp(options_.host.c_str(), options_.port)
             : modbus_new_rtu(options_.serial_device.c_str(), options_.baud, options_.parity, 8, 1);
  if (ctx_ == nullptr) return std::unexpected(ErrnoText("modbus_new"));
  modbus_set_debug(ctx_, options_.debug ? 1 : 0);
  if (modbus_set_slave(ctx_, options_.unit_id) == -1) {
    auto error = ErrnoText("modbus_set_slave");
    CloseAll();
    return std::unexpected(error);
  }
  if (tcp) {
    listen_fd_ = modbus_tcp_listen(ctx_, 8);
    if (listen_fd_ == -1) {
      auto error =
          ErrnoText(("listen on " + options_.host + ":" + std::to_string(options_.port)).c_str());
      CloseAll();
      return std::unexpected(error);
    }
  } else if (modbus_connect(ctx_) == -1) {
    auto error = ErrnoText(("open " + options_.serial_device).c_str());
    CloseAll();
    return std::unexpected(error);
  }
  if (options_.map_version < modbus_rate_table::kOldestMapVersion ||
      options_.map_version > modbus_rate_table::kMapVersion) {
    CloseAll();
    return std::unexpected("map version " + std::to_string(options_.map_version) +
                           " is not one this simulator serves (1 or 2)");
  }
  mapping_ = modbus_mapping_new(0, 0, holding::kCount, InputCount());
  if (mapping_ == nullptr) {
    CloseAll();
    return std::unexpected("modbus_mapping_new failed");
  }
  const auto accel =
      modbus_rate_table::EncodeFloat32(static_cast<float>(physics_.accel_limit_rad_s2()));
  mapping_->tab_registers[holding::kAccelLimit] = accel[0];
  mapping_->tab_registers[holding::kAccelLimit + 1] = accel[1];
  mapping_->tab_registers[holding::kWatchdogMs] = physics_.watchdog_ms();
  RefreshInputRegisters(0, input::kStatusCount);
  return {};
}

int ModbusTableServer::InputCount() const {
  return options_.map_version >= modbus_rate_table::kFirstMapVersionWithAngle ? input::kCount
                                                                              : input::kStatusCount;
}

void ModbusTableServer::CloseAll() noexcept {
  for (int fd : clients_) ::close(fd);
  clients_.clear();
  if (listen_fd_ != -1) ::close(listen_fd_);
  listen_fd_ = -1;
  if (ctx_ != nullptr) {
    if (options_.transport == TableServerOptions::Transport::kTcp) {
      modbus_set_socket(ctx_, -1);  // its socket was one of clients_, closed above
    } else {
      modbus_close(ctx_);  // restores the serial line settings
    }
    modbus_free(ctx_);
    ctx_ = nullptr;
  }
  if (mapping_ != nullptr) modbus_mapping_free(mapping_);
  mapping_ = nullptr;
}

void ModbusTableServer::RequestStop() noexcept {
  stop_.store(true);
  try {
    std::lock_guard lock(mutex_);
  } catch (...) {
  }
  stop_cv_.notify_all();
}

void ModbusTableServer::SleepUnlessStopped(int ms) {
  std::unique_lock lock(mutex_);
  stop_cv_.wait_for(lock, std::chrono::milliseconds(ms), [this] { return stop_.load(); });
}

void ModbusTableServer::AddFault(const FaultRule& rule) {
  std::lock_guard lock(mutex_);
  faults_.push_back(rule);
}

void ModbusTableServer::ClearFaults() {
  std::lock_guard lock(mutex_);
  faults_.clear();
}

TableServerCounters ModbusTableServer::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

bool ModbusTableServer::TakeFault(RegisterTable table, int address, int count, FaultRule* fault) {
  std::lock_guard lock(mutex_);
  ++counters_.requests;
  for (auto& rule : faults_) {
    if (rule.table != table || rule.address < address || rule.address >= address + count ||
        rule.count == 0) {
      continue;
    }
    if (rule.count > 0) --rule.count;
    *fault = rule;
    switch (rule.kind) {
      case FaultKind::kException:
        ++counters_.injected_exceptions;
        break;
      case FaultKind::kLateReply:
        ++counters_.injected_late_replies;
        break;
      case FaultKind::kWrongLength:
        ++counters_.injected_wrong_lengths;
        break;
    }
    return true;
  }
  return false;
}

void ModbusTableServer::RefreshInputRegisters(int address, int count) {
  const auto covers = [&](int first, int n) {
    return address < first + n && first < address + count;
  };
  if (covers(0, input::kStatusCount)) {
    const auto block = modbus_rate_table::EncodeStatusBlock(
        physics_.Status(), static_cast<std::uint16_t>(options_.map_version));
    std::copy(block.begin(), block.end(), mapping_->tab_input_registers);
  }
  if (InputCount() > input::kAngleFirst && covers(input::kAngleFirst, input::kAngleCount)) {
    const auto block = modbus_rate_table::EncodeAngleBlock(physics_.Angle());
    std::copy(block.begin(), block.end(), mapping_->tab_input_registers + input::kAngleFirst);
  }
}

std::array<std::uint16_t, holding::kCount> ModbusTableServer::ImageAfterWrite(
    const std::uint8_t* query, int function, int address, int count) const {
  std::array<std::uint16_t, holding::kCount> regs{};
  std::copy_n(mapping_->tab_registers, holding::kCount, regs.begin());
  const int hl = modbus_get_header_length(ctx_);
  const int offset0 = function == kFnWriteSingle ? hl + 3 : hl + 6;
  for (int i = 0; i < count; ++i) {
    regs[static_cast<std::size_t>(address + i)] =
        static_cast<std::uint16_t>(GetU16(query, offset0 + 2 * i));
  }
  return regs;
}

int ModbusTableServer::CheckWrite(const std::uint8_t* query, int function, int address, int count) {
  const int hl = modbus_get_header_length(ctx_);
  // libmodbus' own checks, in its order, made here because the registers are decoded below.
  if (function == kFnWriteMultiple &&
      (count < 1 || count > MODBUS_MAX_WRITE_REGISTERS || query[hl + 5] != 2 * count)) {
    return modbus_rate_table::exception_code::kIllegalDataValue;
  }
  if (address + count > holding::kCount)
    return modbus_rate_table::exception_code::kIllegalDataAddress;
  const auto covers = [&](int reg) { return reg >= address && reg < address + count; };
  // A float32 is one value in two registers: half of it would command a torn value (a new high
  // word with the old low word), which a real controller refuses as an address error.
  for (int first : holding::kFloatPairs) {
    if (covers(first) != covers(first + 1)) {
      return modbus_rate_table::exception_code::kIllegalDataAddress;
    }
  }
  // Every value of the register image the write would leave must be in range.
  const auto regs = ImageAfterWrite(query, function, address, count);
  const auto& o = physics_.options();
  const double rate = modbus_rate_table::DecodeFloat32(regs[holding::kRateCommand],
                                                       regs[holding::kRateCommand + 1]);
  const double accel =
      modbus_rate_table::DecodeFloat32(regs[holding::kAccelLimit], regs[holding::kAccelLimit + 1]);
  const bool in_range = regs[holding::kMode] <= 1 && regs[holding::kReserved1] == 0 &&
                        std::isfinite(rate) && std::abs(rate) <= o.max_rate_rad_s &&
                        std::isfinite(accel) && accel > 0.0 && accel <= o.max_accel_rad_s2 &&
                        regs[holding::kWatchdogMs] >= modbus_rate_table::kMinWatchdogMs &&
                        regs[holding::kWatchdogMs] <= modbus_rate_table::kMaxWatchdogMs &&
                        regs[holding::kFaultReset] <= 1;
  if (!in_range) return modbus_rate_table::exception_code::kIllegalDataValue;
  // A well-formed motion command the table cannot carry out now. A stop (mode 0, rate 0) is never
  // refused: it is what a faulted table does anyway, and a safe stop must always be possible.
  const bool commands_motion = (covers(holding::kMode) && regs[holding::kMode] == 1) ||
                               (covers(holding::kRateCommand) && rate != 0.0);
  if (commands_motion && physics_.LatchedFaultCode() != 0) {
    return modbus_rate_table::exception_code::kServerDeviceFailure;
  }
  return 0;
}

bool ModbusTableServer::ApplyWrite(const std::uint8_t* query, int function, int address,
                                   int count) {
  const auto covers = [&](int reg) { return reg >= address && reg < address + count; };
  const auto regs = ImageAfterWrite(query, function, address, count);
  // The command first: the physics may still refuse it (the interlock is open, which trips
  // fault 3, or a fault tripped since CheckWrite), and then nothing of the request is applied.
  if (covers(holding::kMode) || covers(holding::kRateCommand)) {
    const bool accepted =
        physics_.Command(static_cast<hw::RateTableMode>(regs[holding::kMode]),
                         modbus_rate_table::DecodeFloat32(regs[holding::kRateCommand],
                                                          regs[holding::kRateCommand + 1]));
    if (!accepted) return false;
  }
  std::copy(regs.begin(), regs.end(), mapping_->tab_registers);
  if (covers(holding::kAccelLimit)) {
    physics_.SetAccelLimit(modbus_rate_table::DecodeFloat32(regs[holding::kAccelLimit],
                                                            regs[holding::kAccelLimit + 1]));
  }
  if (covers(holding::kWatchdogMs)) physics_.SetWatchdogMs(regs[holding::kWatchdogMs]);
  if (covers(holding::kHeartbeat)) {
    physics_.Heartbeat(regs[holding::kHeartbeat]);
    std::lock_guard lock(mutex_);
    ++counters_.heartbeats;
  }
  if (covers(holding::kFaultReset) && regs[holding::kFaultReset] == 1) physics_.ResetFault();
  return true;
}

void ModbusTableServer::RefreshHoldingRegisters() {
  // The mode register reads what the table is doing: a fault (watchdog, e-stop, ...) drops it to
  // idle, so a client reading it back never sees rate mode on a table that stopped itself.
  mapping_->tab_registers[holding::kMode] = static_cast<std::uint16_t>(physics_.ActiveMode());
  mapping_->tab_registers[holding::kFaultReset] = 0;  // a command, not a setting: reads 0
}

void ModbusTableServer::Refuse(const std::uint8_t* query, int exception_code) {
  {
    std::lock_guard lock(mutex_);
    switch (exception_code) {
      case modbus_rate_table::exception_code::kIllegalFunction:
        ++counters_.illegal_functions;
        break;
      case modbus_rate_table::exception_code::kIllegalDataAddress:
        ++counters_.illegal_addresses;
        break;
      case modbus_rate_table::exception_code::kIllegalDataValue:
        ++counters_.rejected_writes;
        break;
      case modbus_rate_table::exception_code::kServerDeviceFailure:
        ++counters_.refused_commands;
        break;
    }
  }
  modbus_reply_exception(ctx_, query, static_cast<unsigned int>(exception_code));
}

void ModbusTableServer::Serve(std::uint8_t* query, int length) {
  const int hl = modbus_get_header_length(ctx_);
  const int function = query[hl];
  const int address = GetU16(query, hl + 1);
  RegisterTable table = RegisterTable::kHolding;
  int count = 1;
  switch (function) {
    case kFnReadInput:
      table = RegisterTable::kInput;
      count = GetU16(query, hl + 3);
      break;
    case kFnReadHolding:
    case kFnWriteMultiple:
      count = GetU16(query, hl + 3);
      break;
    case kFnWriteSingle:
      break;
    case kFnMaskWrite:
    case kFnWriteAndRead:
      // libmodbus would serve them straight from the register map, around every check here; the
      // register map does not offer them, as many controllers do not.
      Refuse(query, modbus_rate_table::exception_code::kIllegalFunction);
      return;
    default:
      modbus_reply(ctx_, query, length, mapping_);
      return;  // libmodbus' exceptions (no coils or discrete inputs: 02; unknown function: 01)
  }
  FaultRule fault;
  if (TakeFault(table, address, count, &fault)) {
    switch (fault.kind) {
      case FaultKind::kException:
        modbus_reply_exception(ctx_, query, fault.exception_code);
        return;
      case FaultKind::kLateReply:
        SleepUnlessStopped(options_.late_reply_ms);
        if (stop_.load()) return;
        break;
      case FaultKind::kWrongLength:
        // As libmodbus' unit-test-server: answer for a different quantity than was asked.
        if (function == kFnReadHolding || function == kFnReadInput) {
          SetU16(query, hl + 3, count > 1 ? count - 1 : count + 1);
        }
        break;
    }
  }
  RefreshHoldingRegisters();
  if (function == kFnReadInput) RefreshInputRegisters(address, count);
  const bool write = function == kFnWriteSingle || function == kFnWriteMultiple;
  if (write) {
    if (const int refusal = CheckWrite(query, function, address, count); refusal != 0) {
      Refuse(query, refusal);
      return;
    }
    // A write takes effect before it is acknowledged, as on a real controller: a client that
    // reads the table right after the reply must see it (the reply-then-apply order raced under
    // load).
    if (!ApplyWrite(query, function, address, count)) {
      RefreshHoldingRegisters();
      Refuse(query, modbus_rate_table::exception_code::kServerDeviceFailure);
      return;
    }
  }
  modbus_reply(ctx_, query, length, mapping_);  // -1: the client went away; nothing to undo
  // The reply copied the written values into the map again: fault reset reads 0, and the mode
  // is the table's (a command accepted by the physics is what it does, until a fault).
  if (write) RefreshHoldingRegisters();
}

std::expected<void, std::string> ModbusTableServer::Run() {
  if (ctx_ == nullptr) return std::unexpected("Run() before a successful Open()");
  std::array<std::uint8_t, MODBUS_TCP_MAX_ADU_LENGTH> query{};
  const bool tcp = options_.transport == TableServerOptions::Transport::kTcp;
  std::vector<pollfd> fds;
  while (!stop_.load()) {
    fds.clear();
    if (tcp) {
      fds.push_back({listen_fd_, POLLIN, 0});
      for (int fd : clients_) fds.push_back({fd, POLLIN, 0});
    } else {
      fds.push_back({modbus_get_socket(ctx_), POLLIN, 0});
    }
    const int n = ::poll(fds.data(), fds.size(), options_.poll_ms);
    if (n < 0 && errno != EINTR) return std::unexpected(ErrnoText("poll"));
    if (n <= 0) continue;
    if (!tcp) {
      if ((fds[0].revents & (POLLERR | POLLNVAL)) != 0) {
        return std::unexpected("serial device " + options_.serial_device + " failed");
      }
      const int rc = modbus_receive(ctx_, query.data());
      if (rc > 0) Serve(query.data(), rc);
      if (rc == -1) {
        if (errno == EBADF || errno == EIO) {
          return std::unexpected(ErrnoText(("read " + options_.serial_device).c_str()));
        }
        modbus_flush(ctx_);  // CRC or framing error: drop the rest, as a real slave does
      }
      continue;
    }
    if ((fds[0].revents & POLLIN) != 0) {
      const int fd = ::accept(listen_fd_, nullptr, nullptr);
      if (fd >= 0) {
        const int one = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
        clients_.push_back(fd);
        std::lock_guard lock(mutex_);
        ++counters_.clients_accepted;
      }
    }
    for (std::size_t i = 1; i < fds.size(); ++i) {
      if ((fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      modbus_set_socket(ctx_, fds[i].fd);
      const int rc = modbus_receive(ctx_, query.data());
      if (rc > 0) Serve(query.data(), rc);
      if (rc == -1) {  // closed by the client, or garbage: drop this client only
        ::close(fds[i].fd);
        std::erase(clients_, fds[i].fd);
      }
    }
    modbus_set_socket(ctx_, -1);
  }
  return {};
}

}  // namespace hrgbench::drivers::sim
