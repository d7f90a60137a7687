#pragma once
// ModbusTableServer: exposes a TablePhysics as a Modbus TCP server (any number of clients, served
// one request at a time) or an RTU server on a serial device, with the register map of
// drivers/modbus_rate_table/README.md and fault injection (table_fault_rule.hpp).
//
// Writes are validated as the real table would: a mode other than 0/1, a rate beyond the table's
// max_rate, an acceleration beyond max_accel or a watchdog outside 100..60000 ms get exception 03
// (ILLEGAL DATA VALUE) and change nothing.
//
// Threads: Open() and Run() on one thread (the server's; Run blocks). RequestStop(), AddFault(),
// ClearFaults() and counters() from any thread. Run() returns within poll_ms of RequestStop(),
// also when it is holding a late reply back.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <expected>
#include <mutex>
#include <string>
#include <vector>

#include "sim/table_fault_rule.hpp"
#include "sim/table_physics.hpp"

struct _modbus;
struct _modbus_mapping_t;

namespace hrgbench::table_sim {

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
};

struct TableServerCounters {
  std::uint64_t requests = 0;
  std::uint64_t injected_exceptions = 0;
  std::uint64_t injected_late_replies = 0;
  std::uint64_t injected_wrong_lengths = 0;
  std::uint64_t rejected_writes = 0;  // exception 03 for an out-of-range value
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
  bool WriteIsValid(const std::uint8_t* query, int function, int address, int count) const;
  void ApplyWrite(int address, int count);
  void RefreshInputRegisters();
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

}  // namespace hrgbench::table_sim
