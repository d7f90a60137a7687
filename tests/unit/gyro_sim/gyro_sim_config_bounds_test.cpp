// Bounds of the hrg-gyro-sim config file: a path that is a directory says so (it loaded the
// defaults silently), a host name has no control characters and a sane length, a message shows a
// value escaped and cut.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "sim/gyro_sim_config.hpp"

namespace hrgbench::drivers::sim {
namespace {

TEST(GyroSimConfigBounds, PathThatIsADirectorySaysSo) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("hrgbench_gyro_sim_dir_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto config = LoadGyroSimConfig(dir.string());
  std::filesystem::remove_all(dir);
  ASSERT_FALSE(config.has_value());
  EXPECT_EQ(config.error(), dir.string() + ": is a directory, not a file");
}

TEST(GyroSimConfigBounds, NulInTheHostIsRefusedAndShownEscaped) {
  const auto config = ParseGyroSimConfig("[omega]\nmodbus_host = \"a\\u0000b\"\n", "sim.toml");
  ASSERT_FALSE(config.has_value());
  EXPECT_EQ(config.error(),
            "sim.toml:2: omega.modbus_host = \"a\\u0000b\": expected a host name: 1 to 255 bytes, "
            "no control characters");
}

TEST(GyroSimConfigBounds, OneMegabyteHostIsRefusedAndShownCut) {
  const auto config = ParseGyroSimConfig(
      "[omega]\nmodbus_host = \"" + std::string(1'000'000, 'h') + "\"\n", "sim.toml");
  ASSERT_FALSE(config.has_value());
  EXPECT_NE(config.error().find("expected a host name"), std::string::npos);
  EXPECT_LT(config.error().size(), 200u) << config.error().substr(0, 200);
}

TEST(GyroSimConfigBounds, ExciteTimeOf1e12SecondsIsRefused) {
  const auto config = ParseGyroSimConfig("[electronics]\nexcite_time_s = 1e12\n", "sim.toml");
  ASSERT_FALSE(config.has_value());
  EXPECT_NE(config.error().find("excite_time_s must be in [0, 600]"), std::string::npos)
      << config.error();
}

}  // namespace
}  // namespace hrgbench::drivers::sim
