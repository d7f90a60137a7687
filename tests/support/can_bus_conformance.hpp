#pragma once
// The CanBus conformance suite's fixture: any CanBus implementation must pass the tests in
// can_bus_conformance_tests.hpp. A test binary supplies a factory that makes two endpoints on one
// bus (`a` sends, `b` receives, and the other way round), includes can_bus_conformance_tests.hpp in
// exactly one translation unit and instantiates:
//
//   INSTANTIATE_TEST_SUITE_P(Virtual, CanBusConformanceTest,
//       ::testing::Values(CanBusConformanceParam{"virtual", &MakeVirtualPair}),
//       CanBusConformanceName);
//
// and, with the FD-capable transports among them, CanFdConformanceTest likewise.
//
// A factory that cannot make its pair (no AF_CAN in this kernel, no vcan0) returns the reason; the
// tests are then SKIPPED with it, never silently passed. The tests use deltas of the statistics,
// so a transport shared with other traffic still conforms, and no sleeps: every "not received"
// assertion is ordered behind a frame that was received.

#include <gtest/gtest.h>

#include <expected>
#include <functional>
#include <memory>
#include <ostream>
#include <string>

#include "can_frame_assertions.hpp"
#include "hrgbench/hw/can_bus.hpp"

namespace hrgbench::testing {

struct CanBusPair {
  std::shared_ptr<void> owner;  // keeps what the endpoints need (a hub) alive; destroyed last
  std::unique_ptr<hw::CanBus> a;
  std::unique_ptr<hw::CanBus> b;
};

struct CanBusConformanceParam {
  std::string name;
  std::function<std::expected<CanBusPair, std::string>()> make_pair;
  // True where the transport must exist (inside the kernel test VM): unavailable is then a failure.
  bool required = false;
};

inline void PrintTo(const CanBusConformanceParam& param, std::ostream* os) { *os << param.name; }

inline std::string CanBusConformanceName(
    const ::testing::TestParamInfo<CanBusConformanceParam>& info) {
  return info.param.name;
}

class CanBusConformanceTest : public ::testing::TestWithParam<CanBusConformanceParam> {
 protected:
  // Generous: a receive on a loaded CI machine or an emulated (TCG) guest may be late.
  static constexpr std::int64_t kReceiveTimeoutNs = 2'000'000'000;

  void SetUp() override {
    auto pair = GetParam().make_pair();
    if (!pair && GetParam().required) {
      GTEST_FAIL() << "CanBus '" << GetParam().name
                   << "' required but unavailable: " << pair.error();
    }
    if (!pair) GTEST_SKIP() << "CanBus '" << GetParam().name << "' unavailable: " << pair.error();
    pair_ = std::move(*pair);
  }

  hw::CanBus& a() { return *pair_.a; }
  hw::CanBus& b() { return *pair_.b; }
  bool BothFd() { return a().SupportsFd() && b().SupportsFd(); }

  static hw::CanFrame Frame(std::uint32_t id, std::uint8_t length, bool extended = false,
                            std::uint8_t seed = 0) {
    hw::CanFrame frame;
    frame.id = id;
    frame.extended = extended;
    frame.length = length;
    for (std::uint8_t i = 0; i < length; ++i) {
      frame.data[i] = static_cast<std::uint8_t>(seed + 37 * i + 1);
    }
    return frame;
  }

  static hw::CanFrame FdFrame(std::uint32_t id, std::uint8_t length, bool brs,
                              std::uint8_t seed = 0) {
    hw::CanFrame frame = Frame(id, length, false, seed);
    frame.fd = true;
    frame.bit_rate_switch = brs;
    return frame;
  }

  // Sends on `from` and expects exactly that frame next on `to`.
  void ExpectRoundTrip(hw::CanBus& from, hw::CanBus& to, const hw::CanFrame& frame) {
    ASSERT_EQ(from.Send(frame, kReceiveTimeoutNs), hw::CanStatus::kOk)
        << hw::CanFrameToString(frame);
    hw::CanFrame received;
    ASSERT_EQ(to.Receive(&received, kReceiveTimeoutNs, nullptr), hw::CanStatus::kOk)
        << "waiting for " << hw::CanFrameToString(frame);
    EXPECT_TRUE(SameFrame(frame, received));
  }

  CanBusPair pair_;
};

// The CAN FD part of the suite, instantiated only with FD-capable transports: an FD test on a
// classic bus would have nothing to check, so it is not instantiated there rather than skipped.
// A transport instantiated here that turns out not to be FD fails.
class CanFdConformanceTest : public CanBusConformanceTest {
 protected:
  void SetUp() override {
    CanBusConformanceTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    if (!BothFd()) GTEST_FAIL() << "CanBus '" << GetParam().name << "' is not CAN FD capable";
  }
};

}  // namespace hrgbench::testing
