// The simulated table answers what its register map does not allow with the Modbus exception a
// real controller sends (drivers/modbus_rate_table/README.md, "Exception replies"), sent here as
// raw libmodbus requests so nothing of the driver stands between the test and the wire:
//   02 ILLEGAL DATA ADDRESS  half of a float pair, a write straddling two floats, unmapped
//   registers 03 ILLEGAL DATA VALUE    out-of-range values, reserved registers included 04 SERVER
//   DEVICE FAILURE a motion command while a fault is latched or the e-stop is pressed
// and a refused request changes nothing. Then what the driver makes of them, and that the holding
// mode register reads what the table is doing (idle after a watchdog trip).
#include <gtest/gtest.h>
#include <modbus.h>

#include <cerrno>
#include <chrono>
#include <thread>
#include <vector>

#include "modbus_rate_table/modbus_rate_table.hpp"
#include "modbus_rate_table/register_map.hpp"
#include "sim/in_process_rate_table.hpp"
#include "sim_table_fixture.hpp"

namespace hrgbench::drivers::modbus_rate_table {
namespace {

using hw::RateTableErrorCode;
using testing::SimTable;

// "accepted", or libmodbus' text for the errno of a refused request: a failing EXPECT_EQ then
// reads "Illegal data address" against "accepted" rather than two numbers.
std::string Answer(int error_number) {
  return error_number == 0 ? std::string("accepted") : std::string(modbus_strerror(error_number));
}

// One raw libmodbus TCP client of the simulated table.
class RawClient {
 public:
  explicit RawClient(int port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    if (ctx_ == nullptr) return;
    modbus_set_response_timeout(ctx_, 1, 0);
    if (modbus_connect(ctx_) == -1) {
      modbus_free(ctx_);
      ctx_ = nullptr;
    }
  }
  ~RawClient() {
    if (ctx_ == nullptr) return;
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;
  bool connected() const { return ctx_ != nullptr; }

  // FC 06. The answer: "accepted" or the exception's text.
  std::string WriteRegister(int address, std::uint16_t value) {
    errno = 0;
    return Answer(modbus_write_register(ctx_, address, value) == -1 ? errno : 0);
  }
  // FC 16.
  std::string WriteRegisters(int address, std::vector<std::uint16_t> values) {
    errno = 0;
    const int n = static_cast<int>(values.size());
    return Answer(modbus_write_registers(ctx_, address, n, values.data()) == -1 ? errno : 0);
  }
  // FC 22 (mask write) and FC 23 (write and read): not in the table's function set.
  std::string MaskWrite(int address, std::uint16_t and_mask, std::uint16_t or_mask) {
    errno = 0;
    return Answer(modbus_mask_write_register(ctx_, address, and_mask, or_mask) == -1 ? errno : 0);
  }
  std::string WriteAndRead(int address, std::vector<std::uint16_t> values) {
    errno = 0;
    std::vector<std::uint16_t> read(values.size());
    const int n = static_cast<int>(values.size());
    return Answer(modbus_write_and_read_registers(ctx_, address, n, values.data(), address, n,
                                                  read.data()) == -1
                      ? errno
                      : 0);
  }
  // FC 03 / FC 04: the registers, or empty when refused (errno_out gets the answer).
  std::vector<std::uint16_t> ReadHolding(int address, int count, std::string* answer = nullptr) {
    return Read(modbus_read_registers, address, count, answer);
  }
  std::vector<std::uint16_t> ReadInput(int address, int count, std::string* answer = nullptr) {
    return Read(modbus_read_input_registers, address, count, answer);
  }

 private:
  std::vector<std::uint16_t> Read(int (*read)(modbus_t*, int, int, std::uint16_t*), int address,
                                  int count, std::string* answer) {
    std::vector<std::uint16_t> regs(static_cast<std::size_t>(count));
    errno = 0;
    const int rc = read(ctx_, address, count, regs.data());
    if (answer != nullptr) *answer = Answer(rc == count ? 0 : errno);
    if (rc != count) regs.clear();
    return regs;
  }

  modbus_t* ctx_;
};

std::vector<std::uint16_t> Float32(float value) {
  const auto words = EncodeFloat32(value);
  return {words[0], words[1]};
}

std::vector<std::uint16_t> Cat(std::vector<std::uint16_t> a, const std::vector<std::uint16_t>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

const std::string kIllegalAddress = Answer(EMBXILADD);
const std::string kIllegalValue = Answer(EMBXILVAL);
const std::string kDeviceFailure = Answer(EMBXSFAIL);
const std::string kIllegalFunction = Answer(EMBXILFUN);
const std::string kAccepted = Answer(0);

class TableExceptions : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(sim_.Start(), "") << "no simulator server";
    client_ = std::make_unique<RawClient>(sim_.port());
    ASSERT_TRUE(client_->connected());
  }

  // The holding registers 0..8 as the table reports them.
  std::vector<std::uint16_t> Holding() { return client_->ReadHolding(0, holding::kCount); }

  // Nothing of a refused request may have reached the table: still at power-on.
  void ExpectUntouched() {
    const auto regs = Holding();
    ASSERT_EQ(regs.size(), static_cast<std::size_t>(holding::kCount));
    EXPECT_EQ(regs[holding::kMode], 0);
    EXPECT_EQ(regs[holding::kReserved1], 0);
    EXPECT_EQ(DecodeFloat32(regs[holding::kRateCommand], regs[holding::kRateCommand + 1]), 0.0f);
    EXPECT_EQ(DecodeFloat32(regs[holding::kAccelLimit], regs[holding::kAccelLimit + 1]), 1.0f);
    EXPECT_EQ(regs[holding::kHeartbeat], 0);
    EXPECT_EQ(regs[holding::kWatchdogMs], 1000);
    EXPECT_EQ(regs[holding::kFaultReset], 0);
    const auto s = sim_.physics().Status();
    EXPECT_EQ(s.mode, hw::RateTableMode::kIdle);
    EXPECT_EQ(s.commanded_rate_rad_s, 0.0);
    EXPECT_EQ(s.heartbeat_echo, 0);
    EXPECT_EQ(sim_.physics().accel_limit_rad_s2(), 1.0);
    EXPECT_EQ(sim_.physics().watchdog_ms(), 1000);
  }

  SimTable sim_;
  std::unique_ptr<RawClient> client_;
};

TEST_F(TableExceptions, SingleRegisterWriteToHalfAFloatIsIllegalDataAddress) {
  // Each value would be in range if combined with the other half now in the table (rate 1.0,
  // rate 9e-41, accel 2.0, accel 1.0000001): the refusal is for the address, not the value.
  EXPECT_EQ(client_->WriteRegister(holding::kRateCommand, 0x3F80), kIllegalAddress);
  EXPECT_EQ(client_->WriteRegister(holding::kRateCommand + 1, 0x0001), kIllegalAddress);
  EXPECT_EQ(client_->WriteRegister(holding::kAccelLimit, 0x4000), kIllegalAddress);
  EXPECT_EQ(client_->WriteRegister(holding::kAccelLimit + 1, 0x0001), kIllegalAddress);
  // FC 16 of one register is the same request.
  EXPECT_EQ(client_->WriteRegisters(holding::kRateCommand, {0x3F80}), kIllegalAddress);
  ExpectUntouched();
  EXPECT_EQ(sim_.server().counters().illegal_addresses, 5u);
}

TEST_F(TableExceptions, MultiRegisterWriteStraddlingOrSplittingAFloatIsIllegalDataAddress) {
  // mode, reserved and the rate's high word only: would command 0.25 rad/s from a torn float.
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, {1, 0, 0x3E80}), kIllegalAddress);
  // reserved + the rate's high word.
  EXPECT_EQ(client_->WriteRegisters(holding::kReserved1, {0, 0x3F80}), kIllegalAddress);
  // the rate's low word + the acceleration's high word: straddles two floats.
  EXPECT_EQ(client_->WriteRegisters(holding::kRateCommand + 1, {0, 0x3F80}), kIllegalAddress);
  // the acceleration's low word + heartbeat + watchdog.
  EXPECT_EQ(client_->WriteRegisters(holding::kAccelLimit + 1, {0, 7, 500}), kIllegalAddress);
  ExpectUntouched();
  // Whole pairs are fine.
  EXPECT_EQ(client_->WriteRegisters(holding::kRateCommand, Cat(Float32(0.0f), Float32(1.0f))),
            kAccepted);
}

TEST_F(TableExceptions, UnmappedRegistersAndUnsupportedFunctionsAreRefused) {
  EXPECT_EQ(client_->WriteRegister(holding::kCount, 0), kIllegalAddress);
  EXPECT_EQ(client_->WriteRegisters(holding::kFaultReset, {0, 0}), kIllegalAddress);
  std::string answer;
  EXPECT_TRUE(client_->ReadHolding(0, holding::kCount + 1, &answer).empty());
  EXPECT_EQ(answer, kIllegalAddress);
  EXPECT_TRUE(client_->ReadInput(0, input::kCount + 1, &answer).empty());
  EXPECT_EQ(answer, kIllegalAddress);
  // Mask write and write-and-read would put values into the registers around every check above
  // (here: mode 1, motion with no validation at all); the table does not implement them.
  EXPECT_EQ(client_->MaskWrite(holding::kMode, 0x0000, 0x0001), kIllegalFunction);
  EXPECT_EQ(client_->WriteAndRead(holding::kMode, {1}), kIllegalFunction);
  ExpectUntouched();
  EXPECT_EQ(sim_.server().counters().illegal_functions, 2u);
}

TEST_F(TableExceptions, OutOfRangeValuesAreIllegalDataValueReservedRegistersIncluded) {
  EXPECT_EQ(client_->WriteRegister(holding::kReserved1, 1), kIllegalValue);
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({0, 0xFFFF}, Float32(0.0f))),
            kIllegalValue);
  EXPECT_EQ(client_->WriteRegister(holding::kFaultReset, 2), kIllegalValue);
  // The rules that were already there.
  EXPECT_EQ(client_->WriteRegister(holding::kMode, 2), kIllegalValue);
  EXPECT_EQ(client_->WriteRegister(holding::kWatchdogMs, 99), kIllegalValue);
  EXPECT_EQ(client_->WriteRegisters(holding::kRateCommand, Float32(25.0f)), kIllegalValue);
  EXPECT_EQ(client_->WriteRegisters(holding::kAccelLimit, Float32(0.0f)), kIllegalValue);
  ExpectUntouched();
  // In range: the reserved register takes its 0, fault reset 0 (nothing) and 1 (reset).
  EXPECT_EQ(client_->WriteRegister(holding::kReserved1, 0), kAccepted);
  EXPECT_EQ(client_->WriteRegister(holding::kFaultReset, 0), kAccepted);
  EXPECT_EQ(client_->WriteRegister(holding::kFaultReset, 1), kAccepted);
}

TEST_F(TableExceptions, MotionCommandsWhileFaultedAreServerDeviceFailure) {
  sim_.physics().InjectFault(hw::RateTableFault::kDrive);
  EXPECT_EQ(client_->WriteRegister(holding::kMode, 1), kDeviceFailure);
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.5f))), kDeviceFailure);
  // A non-zero setpoint is refused too, even with the mode left idle: nothing is stored that a
  // later "mode 1" would start.
  EXPECT_EQ(client_->WriteRegisters(holding::kRateCommand, Float32(0.5f)), kDeviceFailure);
  const auto regs = Holding();
  ASSERT_EQ(regs.size(), static_cast<std::size_t>(holding::kCount));
  EXPECT_EQ(regs[holding::kMode], 0);
  EXPECT_EQ(DecodeFloat32(regs[holding::kRateCommand], regs[holding::kRateCommand + 1]), 0.0f);
  const auto s = sim_.physics().Status();
  EXPECT_EQ(s.mode, hw::RateTableMode::kIdle);
  EXPECT_EQ(s.fault_code, static_cast<std::uint16_t>(hw::RateTableFault::kDrive));
  EXPECT_EQ(sim_.server().counters().refused_commands, 3u);
  // After a fault reset the same command is accepted.
  EXPECT_EQ(client_->WriteRegister(holding::kFaultReset, 1), kAccepted);
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.5f))), kAccepted);
  EXPECT_EQ(sim_.physics().Status().mode, hw::RateTableMode::kRate);
}

TEST_F(TableExceptions, MotionCommandsInEStopAreServerDeviceFailureUntilReleasedAndReset) {
  sim_.physics().SetEStop(true);
  EXPECT_EQ(client_->WriteRegister(holding::kMode, 1), kDeviceFailure);
  EXPECT_EQ(client_->WriteRegister(holding::kFaultReset, 1), kAccepted);  // kept: still pressed
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.2f))), kDeviceFailure);
  EXPECT_EQ(Holding().at(holding::kMode), 0);
  sim_.physics().SetEStop(false);
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.2f))), kDeviceFailure);
  EXPECT_EQ(client_->WriteRegister(holding::kFaultReset, 1), kAccepted);
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.2f))), kAccepted);
  EXPECT_EQ(Holding().at(holding::kMode), 1);
}

TEST_F(TableExceptions, RateModeWithTheInterlockOpenTripsAndIsServerDeviceFailure) {
  sim_.physics().SetInterlockOpen(true);  // standing still: no trip yet
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.2f))), kDeviceFailure);
  const auto s = sim_.physics().Status();
  EXPECT_EQ(s.fault_code, static_cast<std::uint16_t>(hw::RateTableFault::kInterlock));
  EXPECT_EQ(Holding().at(holding::kMode), 0);
}

TEST_F(TableExceptions, StopCommandsAndSettingsAreAcceptedWhileFaulted) {
  // A safe stop must always be possible, and the settings do not move the table.
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.3f))), kAccepted);
  sim_.physics().SetEStop(true);
  EXPECT_EQ(client_->WriteRegisters(holding::kMode, Cat({0, 0}, Float32(0.0f))), kAccepted);
  EXPECT_EQ(client_->WriteRegister(holding::kMode, 0), kAccepted);
  EXPECT_EQ(client_->WriteRegisters(holding::kRateCommand, Float32(0.0f)), kAccepted);
  EXPECT_EQ(client_->WriteRegisters(holding::kAccelLimit, Float32(2.0f)), kAccepted);
  EXPECT_EQ(client_->WriteRegister(holding::kHeartbeat, 42), kAccepted);
  EXPECT_EQ(client_->WriteRegister(holding::kWatchdogMs, 500), kAccepted);
  EXPECT_EQ(client_->WriteRegister(holding::kFaultReset, 1), kAccepted);
  const auto s = sim_.physics().Status();
  EXPECT_EQ(s.mode, hw::RateTableMode::kIdle);
  EXPECT_EQ(s.heartbeat_echo, 42);
  EXPECT_EQ(sim_.physics().accel_limit_rad_s2(), 2.0);
  EXPECT_EQ(sim_.physics().watchdog_ms(), 500);
}

TEST_F(TableExceptions, ModeRegisterReadsIdleAfterAWatchdogTrip) {
  ASSERT_EQ(client_->WriteRegister(holding::kWatchdogMs, 100), kAccepted);
  ASSERT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.2f))), kAccepted);
  EXPECT_EQ(Holding().at(holding::kMode), 1);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));  // no heartbeat: trips at 100 ms
  const auto status = client_->ReadInput(0, input::kCount);
  ASSERT_EQ(status.size(), static_cast<std::size_t>(input::kCount));
  ASSERT_NE(status[input::kStatusBits] & status_bit::kFault, 0);
  EXPECT_EQ(status[input::kFaultCode], static_cast<std::uint16_t>(hw::RateTableFault::kWatchdog));
  EXPECT_EQ(status[input::kMode], 0);
  const auto regs = Holding();
  ASSERT_EQ(regs.size(), static_cast<std::size_t>(holding::kCount));
  EXPECT_EQ(regs[holding::kMode], status[input::kMode]) << "holding mode disagrees with status";
  // The setpoint is a parameter, kept; the table follows it again only after reset + mode 1.
  EXPECT_EQ(DecodeFloat32(regs[holding::kRateCommand], regs[holding::kRateCommand + 1]), 0.2f);
}

TEST_F(TableExceptions, ModeRegisterReadsIdleAfterAnEStop) {
  ASSERT_EQ(client_->WriteRegisters(holding::kMode, Cat({1, 0}, Float32(0.2f))), kAccepted);
  sim_.physics().SetEStop(true);
  EXPECT_EQ(Holding().at(holding::kMode), 0);
  EXPECT_EQ(client_->ReadInput(0, input::kCount).at(input::kMode), 0);
}

// ---- What the driver makes of them ----

class DriverAgainstRefusals : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(sim_.Start(), "") << "no simulator server"; }
  ModbusRateTableConfig QuietConfig() const {
    auto config = sim_.DriverConfig();
    // No heartbeat falls due during a test, so the transactions counted are the ones asked for.
    config.watchdog_timeout_ms = 20000;
    config.heartbeat_period_ms = 10000;
    return config;
  }
  SimTable sim_;
  hw::SteadyClock clock_;
};

TEST_F(DriverAgainstRefusals, RateCommandToATableThatFaultedSinceTheLastStatusIsFaulted) {
  ModbusRateTable table(QuietConfig(), clock_);
  ASSERT_TRUE(table.Connect());
  ASSERT_TRUE(table.SetRate(0.3));
  sim_.physics().SetEStop(true);  // the driver has not read a status since: it thinks connected
  ASSERT_EQ(table.state(), TableLinkState::kConnected);
  const auto before = table.counters();
  const auto r = table.SetRate(0.5);
  ASSERT_FALSE(r) << "a rate command to an e-stopped table was reported as accepted";
  EXPECT_EQ(r.error().code, RateTableErrorCode::kFaulted) << r.error().ToString();
  EXPECT_NE(r.error().message.find("refused"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("e-stop"), std::string::npos) << r.error().message;
  EXPECT_EQ(table.state(), TableLinkState::kFaulted);
  // One refused write, one status read to say why; never retried.
  const auto after = table.counters();
  EXPECT_EQ(after.exception_replies - before.exception_replies, 1u);
  EXPECT_EQ(after.transactions - before.transactions, 2u);
  EXPECT_EQ(table.target_rate_rad_s(), 0.3f);  // unchanged: the table did not take 0.5
  EXPECT_EQ(sim_.physics().Status().mode, hw::RateTableMode::kIdle);
}

TEST_F(DriverAgainstRefusals, StopAndSafeStopAreAcceptedByAFaultedTable) {
  ModbusRateTable table(QuietConfig(), clock_);
  ASSERT_TRUE(table.Connect());
  ASSERT_TRUE(table.SetRate(0.3));
  sim_.physics().SetEStop(true);
  ASSERT_TRUE(table.ReadStatus());
  ASSERT_EQ(table.state(), TableLinkState::kFaulted);
  const auto stopped = table.Stop();
  EXPECT_TRUE(stopped) << stopped.error().ToString();
  table.SafeStop();
  EXPECT_EQ(table.counters().exception_replies, 0u);
  const auto s = sim_.physics().Status();
  EXPECT_EQ(s.mode, hw::RateTableMode::kIdle);
  EXPECT_EQ(s.commanded_rate_rad_s, 0.0);
}

// The in-process table (drivers/sim_station) claims the Modbus table's observable semantics: the
// same refused command gives the same error code and state, and leaves the table where it was.
TEST_F(DriverAgainstRefusals, InProcessTableRefusesACommandWhileFaultedAsTheModbusTableDoes) {
  ModbusRateTable modbus(QuietConfig(), clock_);
  ASSERT_TRUE(modbus.Connect());
  sim::TablePhysics physics(testing::FastTable(), clock_);
  sim_station::InProcessRateTableConfig in_process_config;
  in_process_config.accel_limit_rad_s2 = 2.0;
  sim_station::InProcessRateTable in_process(in_process_config, physics, clock_);
  ASSERT_TRUE(in_process.Connect());

  sim_.physics().InjectFault(hw::RateTableFault::kDrive);
  physics.InjectFault(hw::RateTableFault::kDrive);
  const auto modbus_refused = modbus.SetRate(0.5);
  const auto in_process_refused = in_process.SetRate(0.5);
  ASSERT_FALSE(modbus_refused);
  ASSERT_FALSE(in_process_refused);
  EXPECT_EQ(modbus_refused.error().code, in_process_refused.error().code)
      << "modbus: " << modbus_refused.error().ToString()
      << "\nin-process: " << in_process_refused.error().ToString();
  EXPECT_EQ(modbus_refused.error().code, RateTableErrorCode::kFaulted);
  for (const auto* message :
       {&modbus_refused.error().message, &in_process_refused.error().message}) {
    EXPECT_NE(message->find("drive"), std::string::npos) << *message;
  }
  EXPECT_EQ(modbus.state(), TableLinkState::kFaulted);
  EXPECT_EQ(in_process.state(), modbus_rate_table::TableLinkState::kFaulted);
  EXPECT_EQ(modbus.target_rate_rad_s(), in_process.target_rate_rad_s());
  // Stop is accepted by both while faulted.
  EXPECT_TRUE(modbus.Stop());
  EXPECT_TRUE(in_process.Stop());
  EXPECT_EQ(sim_.physics().Status().mode, physics.Status().mode);
}

}  // namespace
}  // namespace hrgbench::drivers::modbus_rate_table
