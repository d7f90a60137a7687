#pragma once
// ModbusTableServer: exposes a TablePhysics as a Modbus TCP server (any number of clients, served
// one request at a time) or an RTU server on a serial device, with the register map of
// drivers/modbus_rate_table/README.md and fault injection (table_fault_rule.hpp).
//
// Writes are validated as the real table would, per register as register_map.hpp and README.md
// in drivers/modbus_rate_table document, and a refused write changes nothing:
//   02 ILLEGAL DATA ADDRESS  a register outside 0..8, or a write covering half of a float32 pair;
//   03 ILLEGAL DATA VALUE    mode not 0/1, reserved not 0, |rate| > max_rate, acceleration not in
//                            (0, max_accel], watchdog outside 100..60000 ms, fault reset not 0/1;
//   04 SERVER DEVICE FAILURE mode 1 or a non-zero rate while a fault is latched or the e-stop is
//                            pressed, or mode 1 with the interlock open (which trips fault 3);
//                            mode 0 / rate 0 are always accepted (a stop must always be possible);
//   01 ILLEGAL FUNCTION      FC 22 (mask write) and FC 23 (write and read), not in the map.
// Reads of the input registers are served from the physics at the moment of the request: the
// status block (0..10) from Status(), the angle block (11..15, map version 2) from Angle().
// The holding mode register reads the mode actually active (0 once a fault tripped), so it
// agrees with the status block.
//
// Threads: Open() and Run() on one thread (the server's; Run blocks). RequestStop(), AddFault(),
// ClearFaults() and counters() from any thread. Run() returns within poll_ms of RequestStop(),
// also when it is holding a late reply back.

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <expected>
#include <mutex>
#include <string>
#include <vector>

#include "modbus_rate_table/register_map.hpp"
#include "sim/table_fault_rule.hpp"
#include "sim/table_physics.hpp"

struct _modbus;
struct _modbus_mapping_t;

namespace hrgbench::drivers::sim {

struct TableServerOptions {
  enum class Transport { kTcp, kRtu };
  Transport transport = Transport::kTcp;
  std::string host = "127.0.0.1";
  int port = 1502;  // 502 needs root; 1502 is libmodbus' test port
  std::string serial_device;
  int baud = 115200;
  char parity = 'N';
  int unit_id = 1;           // RTU: requests for other ids are ignored, as on a shared bus
  int late_reply_ms = 1000;  // "late" faults: well beyond the driver's default 200 ms timeout
  int poll_ms = 20;          // granularity of RequestStop()
  bool debug = false;        // libmodbus' frame dump on stdout
  // The register map version served: 2 (the current map, with the encoder angle in input
  // registers 11..15), or 1 (a table of the first map: 11 input registers, no angle; reads past
  // them get exception 02), to test clients against an older table.
  int map_version = modbus_rate_table::kMapVersion;
};

struct TableServerCounters {
  std::uint64_t requests = 0;
  std::uint64_t injected_exceptions = 0;
  std::uint64_t injected_late_replies = 0;
  std::uint64_t injected_wrong_lengths = 0;
  std::uint64_t rejected_writes = 0;    // exception 03: a value out of range
  std::uint64_t illegal_addresses = 0;  // exception 02 to a write: unmapped, or half a float32
  std::uint64_t refused_commands = 0;   // exception 04: motion while faulted / e-stop / interlock
  std::uint64_t illegal_functions = 0;  // exception 01: FC 22, FC 23
  std::uint64_t heartbeats = 0;
  std::uint64_t clients_accepted = 0;
};

class ModbusTableServer {
 public:
  ModbusTableServer(TablePhysics& physics, TableServerOptions options);
  ~ModbusTableServer();
  ModbusTableServer(const ModbusTableServer&) = delete;
  ModbusTableServer& operator=(const ModbusTableServer&) = delete;

  // TCP: listens on host:port (fails, e.g. EADDRINUSE, with a message). RTU: opens the device.
  std::expected<void, std::string> Open();
  // Serves until RequestStop(). Returns an error only when the link breaks (RTU device gone).
  std::expected<void, std::string> Run();
  void RequestStop() noexcept;

  void AddFault(const FaultRule& rule);
  void ClearFaults();
  TableServerCounters counters() const;
  const TableServerOptions& options() const { return options_; }

 private:
  void Serve(std::uint8_t* query, int length);
  bool TakeFault(RegisterTable table, int address, int count, FaultRule* fault);
  // The holding registers as a write (FC 06 / FC 16, already within 0..8) would leave them.
  std::array<std::uint16_t, modbus_rate_table::holding::kCount> ImageAfterWrite(
      const std::uint8_t* query, int function, int address, int count) const;
  // 0 when the write may be applied, else the exception code to answer with.
  int CheckWrite(const std::uint8_t* query, int function, int address, int count);
  // False (and nothing applied) when the physics refuses the command after all.
  bool ApplyWrite(const std::uint8_t* query, int function, int address, int count);
  void Refuse(const std::uint8_t* query, int exception_code);
  void RefreshHoldingRegisters();
  // The input registers a read of [address, address + count) covers, from the physics: the status
  // block draws the rate noise, the angle block the encoder's (each only when read).
  void RefreshInputRegisters(int address, int count);
  int InputCount() const;
  void SleepUnlessStopped(int ms);
  void CloseAll() noexcept;

  TablePhysics& physics_;
  TableServerOptions options_;
  _modbus* ctx_ = nullptr;
  _modbus_mapping_t* mapping_ = nullptr;
  int listen_fd_ = -1;
  std::vector<int> clients_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;  // faults_, counters_, stop_cv_
  std::condition_variable stop_cv_;
  std::vector<FaultRule> faults_;
  TableServerCounters counters_;
};

}  // namespace hrgbench::drivers::sim
