#pragma once
// Shared steps of the recorder integration tests: record a run of synthetic samples, and check
// that a session directory holds exactly the expected complete runs, bit for bit.

#include <gtest/gtest.h>

#include <span>
#include <vector>

#include "hrgbench/session/session.hpp"
#include "hrgbench/session/session_recorder.hpp"
#include "synthetic_gyro_record.hpp"

namespace hrgbench::bench::record_test {

inline constexpr std::size_t kSamplesPerRun = 500;

inline RunStart StartFor(const PlannedRun& plan) {
  RunStart start;
  start.commanded_omega_rad_s = plan.commanded_omega_rad_s;
  start.measured_omega_rad_s = plan.commanded_omega_rad_s;
  start.temperature_c = 25.0;
  start.release_t_ns = 1000 * plan.id;
  return start;
}

inline RunEnd CompleteEnd(const PlannedRun& plan) {
  RunEnd end;
  end.omega_rad_s = plan.commanded_omega_rad_s + 5.1e-5;
  return end;
}

// Returns the first error (no gtest assertions: also used in forked children).
inline std::expected<void, RecordError> RecordRun(SessionRecorder& recorder, const PlannedRun& plan,
                                                  std::size_t samples = kSamplesPerRun) {
  if (auto begun = recorder.BeginRun(plan.id, StartFor(plan)); !begun) return begun;
  const auto data = testing::SyntheticSamples(plan.id, samples, plan.sample_rate_hz);
  for (std::size_t k = 0; k < data.size(); k += 100) {
    const auto batch = std::span(data).subspan(k, std::min<std::size_t>(100, data.size() - k));
    if (auto appended = recorder.AppendSamples(batch); !appended) return appended;
  }
  return recorder.EndRun(CompleteEnd(plan));
}

// The session reads back with exactly `ids` complete, each bit-identical to its synthetic data.
inline void ExpectCompleteRuns(const std::filesystem::path& dir, const SessionHeader& header,
                               const std::vector<int>& ids) {
  auto read = session::ReadSession(dir);
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  ASSERT_EQ(read->loaded_run_ids, ids);
  const auto runs = session::ToRunData(*read);
  for (std::size_t r = 0; r < ids.size(); ++r) {
    const PlannedRun& plan = header.runs[static_cast<std::size_t>(ids[r] - 1)];
    EXPECT_EQ(runs[r].omega_rad_s, CompleteEnd(plan).omega_rad_s);
    const auto expected = testing::SyntheticSamples(plan.id, kSamplesPerRun, plan.sample_rate_hz);
    ASSERT_EQ(runs[r].t_s.size(), expected.size()) << "run " << ids[r];
    for (std::size_t k = 0; k < expected.size(); ++k) {
      ASSERT_EQ(runs[r].t_s[k], expected[k].t_s);
      for (int c = 0; c < 4; ++c) {
        ASSERT_EQ(runs[r].y(c, static_cast<Eigen::Index>(k)), expected[k].y[c]);
      }
    }
  }
}

}  // namespace hrgbench::bench::record_test
