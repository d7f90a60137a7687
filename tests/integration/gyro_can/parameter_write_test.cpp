// The compensation parameter block written to the simulated electronics over the virtual bus
// (issue 28 §2): read back and compared before it is committed, committed to one of two slots of
// their non-volatile memory, and safe whatever fails on the way — a word corrupted in their memory,
// a power loss between write and commit, a block that is not valid. The electronics always keep a
// valid block, and the host can say which.

#include <gtest/gtest.h>

#include <bit>
#include <vector>

#include "gyro_rig.hpp"
#include "hrgbench/bench/tuning/tune_unit.hpp"
#include "hrgbench/estimator/compensation.hpp"
#include "hrgbench/estimator/maximum_likelihood.hpp"
#include "hrgbench/estimator/simulation.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

using hw::GyroErrorCode;
using testing::GyroRig;
using testing::GyroRigOptions;

constexpr ParameterValues kFactory = {-1e-3, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
constexpr ParameterValues kTuned = {-1.02e-3, 0.29137, 3.1e-5,  -1.9e-5, 2.04e-4, -0.98e-4,
                                    0.0101,   0.0019,  -0.0031, 0.0041,  1.7e-6};

TEST(ParameterWriteTest, WritesReadsBackCommitsAndRecordsTheBlockBefore) {
  GyroRig rig(GyroRigOptions{});
  auto before = rig.device->ReadParameters();
  ASSERT_TRUE(before.has_value()) << before.error().ToString();
  EXPECT_EQ(*before, kFactory);

  auto written = rig.device->WriteParameters(kTuned);
  ASSERT_TRUE(written.has_value()) << written.error().ToString();
  ASSERT_TRUE(written->previous.has_value());
  EXPECT_EQ(*written->previous, kFactory);
  EXPECT_EQ(written->generation, 2u);
  EXPECT_EQ(rig.node->ActiveParameters(), kTuned);  // what the unit would boot with, bit for bit
  EXPECT_EQ(rig.device->ReadParameters().value(), kTuned);

  // And back to the block before.
  auto restored = rig.device->RestorePreviousParameters();
  ASSERT_TRUE(restored.has_value()) << restored.error().ToString();
  EXPECT_EQ(*restored, 1u);
  EXPECT_EQ(rig.node->ActiveParameters(), kFactory);
  // A second write goes to the slot not active: the tuned block's (generation 2 becomes 2 again:
  // one more than the active block's).
  ASSERT_TRUE(rig.device->WriteParameters(kTuned).has_value());
  EXPECT_EQ(rig.node->ActiveParameterGeneration(), 2u);
}

TEST(ParameterWriteTest, AWordChangedInTheElectronicsMemoryCommitsNothing) {
  GyroRigOptions options;
  options.sim.faults.corrupt_parameter_word = 17;
  GyroRig rig(options);
  auto written = rig.device->WriteParameters(kTuned);
  ASSERT_FALSE(written.has_value());
  EXPECT_EQ(written.error().code, GyroErrorCode::kReadBackMismatch);
  EXPECT_NE(written.error().message.find("staged word 17"), std::string::npos)
      << written.error().message;
  EXPECT_NE(written.error().message.find("nothing committed"), std::string::npos);
  EXPECT_EQ(rig.node->ActiveParameters(), kFactory);
  EXPECT_EQ(rig.node->ActiveParameterGeneration(), 1u);
}

TEST(ParameterWriteTest, APowerLossDuringTheCommitLeavesTheBlockBefore) {
  GyroRigOptions options;
  options.sim.faults.power_loss_on_commit = 1;
  GyroRig rig(options);
  auto written = rig.device->WriteParameters(kTuned);
  ASSERT_FALSE(written.has_value());
  // The Commit's first attempt gets no Ack; its retry reaches electronics that restarted with an
  // empty staging block and refuse it. Either way the host says what they hold now.
  EXPECT_EQ(written.error().code, GyroErrorCode::kRejected) << written.error().ToString();
  EXPECT_NE(written.error().message.find("the electronics hold the block before, unchanged"),
            std::string::npos)
      << written.error().message;
  EXPECT_EQ(rig.node->Statistics().power_losses, 1u);
  // The torn slot fails its CRC: the electronics came back with the block before, and say so.
  EXPECT_EQ(rig.node->ActiveParameterGeneration(), 1u);
  auto now = rig.device->ReadParameters();
  ASSERT_TRUE(now.has_value()) << now.error().ToString();
  EXPECT_EQ(*now, kFactory);
  // Power back: the same write goes through.
  auto again = rig.device->WriteParameters(kTuned);
  ASSERT_TRUE(again.has_value()) << again.error().ToString();
  EXPECT_EQ(again->generation, 2u);
  EXPECT_EQ(rig.node->ActiveParameters(), kTuned);
}

TEST(ParameterWriteTest, TheElectronicsRefuseAnInvalidBlockAndAnythingWhileAWaveRuns) {
  GyroRig rig(GyroRigOptions{});
  // A block whose CRC does not hold, word by word as a host would send it: Commit is refused.
  ParameterBlockWords block = EncodeParameterBlock(kTuned);
  block[20] ^= 0x8000;
  auto endpoint = rig.bus->CreateEndpoint();
  const auto send_and_ack = [&](ParameterCommand command) {
    EXPECT_EQ(endpoint->Send(EncodeParameter(0, command), 0), hw::CanStatus::kOk);
    hw::CanFrame frame;
    for (int i = 0; i < 100; ++i) {
      if (endpoint->Receive(&frame, 1'000'000, nullptr) != hw::CanStatus::kOk) continue;
      Ack ack;
      if (DecodeAck(frame, 0, &ack) == DecodeStatus::kOk && ack.token == command.token) return ack;
    }
    ADD_FAILURE() << "no ack";
    return Ack{};
  };
  std::uint8_t token = 100;
  EXPECT_EQ(send_and_ack({token++, ParameterOp::kBegin, 0, kParameterBlockWords}).result,
            AckResult::kOk);
  for (int i = 0; i < kParameterBlockWords; ++i) {
    send_and_ack({token++, ParameterOp::kWrite, static_cast<std::uint8_t>(i),
                  block[static_cast<std::size_t>(i)]});
  }
  EXPECT_EQ(send_and_ack({token++, ParameterOp::kCommit, 0, 0}).result, AckResult::kBadArgument);
  EXPECT_EQ(send_and_ack({token++, ParameterOp::kWrite, 48, 0}).result, AckResult::kBadArgument);
  EXPECT_EQ(rig.node->ActiveParameters(), kFactory);
  EXPECT_EQ(rig.node->ActiveParameterGeneration(), 1u);

  // Never while the wave is driven or free: the host refuses before sending, the electronics too.
  rig.StartRun(1000, {1.0, 0.0, 0.0});
  auto during = rig.device->WriteParameters(kTuned);
  ASSERT_FALSE(during.has_value());
  EXPECT_EQ(during.error().code, GyroErrorCode::kInvalidState);
  EXPECT_EQ(send_and_ack({token++, ParameterOp::kBegin, 0, kParameterBlockWords}).result,
            AckResult::kBadState);
  EXPECT_EQ(rig.node->ActiveParameters(), kFactory);
}

// The block's eleven values are p's vector, in its order (compensation.hpp, parameter_block.hpp).
static_assert(estimator::kCompensationSize == kParameterValueCount);

TEST(ParameterWriteTest, ACompensationFromAnEstimateReachesTheElectronicsBitForBit) {
  std::vector<estimator::RunPlan> plans;
  const double omegas[] = {0.1, -0.1, 0.3, -0.3, 1.0, -1.0};
  for (int r = 0; r < 6; ++r) {
    plans.push_back({omegas[r], 1.0, 0.1, r * 0.26, 0.0, 100.0, 20.0});
  }
  estimator::SimulationOptions truth;
  truth.delta << -1e-3, 0.29, 3e-5, -2e-5, 2e-4, -1e-4;
  truth.xi << 0.01, 0.002, -0.003, 0.004;
  truth.sigma = 1e-4;
  const auto estimate = estimator::EstimateMaximumLikelihood(estimator::SimulateRuns(plans, truth));
  estimator::CompensationSet p;
  ASSERT_TRUE(estimator::CompensationFromEstimate(estimate, &p)) << estimate.message;

  const ParameterValues values = bench::ToCompensationValues(p);
  const estimator::CompensationVector v = p.AsVector();
  GyroRig rig(GyroRigOptions{});
  ASSERT_TRUE(rig.device->WriteParameters(values).has_value());
  const auto held = rig.node->ActiveParameters();
  ASSERT_TRUE(held.has_value());
  for (int i = 0; i < kParameterValueCount; ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>((*held)[static_cast<std::size_t>(i)]),
              std::bit_cast<std::uint64_t>(v[i]))
        << "value " << i;
  }
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
