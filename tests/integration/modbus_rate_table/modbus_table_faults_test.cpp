// Fault injection at chosen registers, as libmodbus' own unit-test-server does: a reply after the
// timeout, an exception reply, a reply of the wrong length. Each is a status plus a counter.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "modbus_rate_table/modbus_rate_table.hpp"
#include "modbus_rate_table/register_map.hpp"
#include "sim_table_fixture.hpp"

namespace hrgbench::drivers::modbus_rate_table {
namespace {

using hw::RateTableErrorCode;
using sim::FaultKind;
using sim::FaultRule;
using sim::RegisterTable;
using testing::SimTable;
using Seconds = std::chrono::duration<double>;

class ModbusTableFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    sim::TableServerOptions server;
    server.late_reply_ms = 600;
    sim_ = std::make_unique<SimTable>(testing::FastTable(), server);
    ASSERT_EQ(sim_->Start(), "");
    auto config = sim_->DriverConfig();
    config.response_timeout_ms = 100;
    table_ = std::make_unique<ModbusRateTable>(config, clock_);
    ASSERT_TRUE(table_->Connect());
  }
  hw::SteadyClock clock_;
  std::unique_ptr<SimTable> sim_;
  std::unique_ptr<ModbusRateTable> table_;
};

TEST_F(ModbusTableFaults, LateReplyIsATimeoutStatusNotAHang) {
  sim_->server().AddFault({RegisterTable::kInput, input::kMeasuredRate, FaultKind::kLateReply, 1});
  const auto start = std::chrono::steady_clock::now();
  const auto r = table_->ReadStatus();
  const double took_s = Seconds(std::chrono::steady_clock::now() - start).count();
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, RateTableErrorCode::kTimeout) << r.error().ToString();
  EXPECT_GE(table_->counters().timeouts, 1u);
  // Bounded: 2 attempts x 100 ms (+ a reconnect); generous slack, far below "hung".
  EXPECT_LT(took_s, 2.0);
  // Once the server is past its slow reply, the link recovers by itself (bounded reconnect).
  bool recovered = false;
  for (int i = 0; i < 50 && !recovered; ++i) {
    recovered = table_->ReadStatus().has_value();
    if (!recovered) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(recovered);
  EXPECT_GE(table_->counters().reconnects, 1u);
  EXPECT_EQ(sim_->server().counters().injected_late_replies, 1u);
}

TEST_F(ModbusTableFaults, InjectedExceptionReplyIsReportedOnceWithoutRetry) {
  sim_->server().AddFault({RegisterTable::kHolding, holding::kRateCommand, FaultKind::kException});
  const auto r = table_->SetRate(0.3);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, RateTableErrorCode::kExceptionReply);
  EXPECT_NE(r.error().message.find("exception 4"), std::string::npos) << r.error().message;
  EXPECT_EQ(table_->counters().exception_replies, 1u);
  EXPECT_EQ(sim_->physics().Status().mode, hw::RateTableMode::kIdle);  // nothing applied
}

TEST_F(ModbusTableFaults, TableRejectsARateBeyondItsHardwareLimitWithAnException) {
  // Software limit 10 rad/s lets 25 through; the simulated table's own limit is 20 rad/s.
  const auto r = table_->SetRate(9.0);
  ASSERT_TRUE(r) << r.error().ToString();
  auto config = sim_->DriverConfig();
  config.limits.max_rate_rad_s = 30.0;
  ModbusRateTable permissive(config, clock_);
  ASSERT_TRUE(permissive.Connect());
  const auto rejected = permissive.SetRate(25.0);
  ASSERT_FALSE(rejected);
  EXPECT_EQ(rejected.error().code, RateTableErrorCode::kExceptionReply);
  EXPECT_NE(rejected.error().message.find("exception 3"), std::string::npos);
  EXPECT_EQ(sim_->server().counters().rejected_writes, 1u);
}

TEST_F(ModbusTableFaults, OneWrongLengthReplyIsRetriedAndCounted) {
  sim_->server().AddFault({RegisterTable::kInput, input::kStatusBits, FaultKind::kWrongLength, 1});
  const auto r = table_->ReadStatus();
  ASSERT_TRUE(r) << r.error().ToString();  // the second attempt succeeds
  EXPECT_EQ(table_->counters().bad_replies, 1u);
  EXPECT_EQ(sim_->server().counters().injected_wrong_lengths, 1u);
}

TEST_F(ModbusTableFaults, PersistentWrongLengthIsABadReply) {
  sim_->server().AddFault({RegisterTable::kInput, input::kStatusBits, FaultKind::kWrongLength});
  const auto r = table_->ReadStatus();
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, RateTableErrorCode::kBadReply) << r.error().ToString();
  EXPECT_EQ(table_->counters().bad_replies, 2u);  // transaction_attempts = 2
  sim_->server().ClearFaults();
  EXPECT_TRUE(table_->ReadStatus());
}

}  // namespace
}  // namespace hrgbench::drivers::modbus_rate_table
