// The gyro link's planned bus load against drivers/gyro_can/README.md "Bus load", worked by hand
// from worst-case frame times (135 µs for an 8-byte classic frame at 1 Mbit/s; 33 µs + 679 bits
// at the data rate for a 64-byte FD frame with BRS).

#include "hrgbench/hw/gyro_link_load.hpp"

#include <gtest/gtest.h>

namespace hrgbench::hw {
namespace {

TEST(GyroLinkLoad, OneKilohertzOnClassicCanAtOneMegabit) {
  GyroLinkPlan plan;
  plan.sample_rate_hz = 1000;
  plan.reference_phase = false;
  // 2000 sample frames + 10 status frames, 135 µs each.
  GyroLinkLoad load = WorstCaseLinkLoad(plan);
  EXPECT_DOUBLE_EQ(load.frames_per_s, 2010.0);
  EXPECT_NEAR(load.bus_share, 2010 * 135e-6, 1e-12);
  // The reference phase: 200 more frames, +2.7 %.
  plan.reference_phase = true;
  load = WorstCaseLinkLoad(plan);
  EXPECT_NEAR(load.bus_share, 2210 * 135e-6, 1e-12);
  // Half the bit rate, twice the time.
  plan.nominal_bit_rate_bps = 500'000;
  EXPECT_NEAR(WorstCaseLinkLoad(plan).bus_share, 2210 * 270e-6, 1e-12);
}

TEST(GyroLinkLoad, TenKilohertzOnCanFd) {
  GyroLinkPlan plan;
  plan.sample_rate_hz = 10000;
  plan.can_fd = true;
  plan.data_bit_rate_bps = 5'000'000;
  // 2000 FD frames of 33 µs + 135.8 µs, 2000 reference-phase and 10 status frames of 135 µs.
  const GyroLinkLoad load = WorstCaseLinkLoad(plan);
  EXPECT_DOUBLE_EQ(load.frames_per_s, 4010.0);
  EXPECT_NEAR(load.bus_share, 2000 * 168.8e-6 + 2010 * 135e-6, 1e-9);
  // At a 2 Mbit/s data phase the same plan does not fit in 70 %.
  plan.data_bit_rate_bps = 2'000'000;
  EXPECT_GT(WorstCaseLinkLoad(plan).bus_share, kMaxPlannedBusShare);
}

}  // namespace
}  // namespace hrgbench::hw
