// Bounds of the hrg-gyro-sim config file: a path that is a directory says so (it loaded the
// defaults silently), a host name has no control characters and a sane length, a message shows a
// value escaped (as written in the file, never the raw control character) and cut.

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
  EXPECT_EQ(config.error().ToString(), dir.string() + ": is a directory, not a file");
}

TEST(GyroSimConfigBounds, NulInTheHostIsRefusedAndShownEscaped) {
  const auto config = ParseGyroSimConfig("[omega]\nmodbus_host = \"a\\u0000b\"\n", "sim.toml");
  ASSERT_FALSE(config.has_value());
  EXPECT_EQ(config.error().ToString(),
            "sim.toml:2: key 'omega.modbus_host' = \"a\\u0000b\": out of range: control character "
            "U+0000 at byte 1; a name is printable text on one line");
}

TEST(GyroSimConfigBounds, OneMegabyteHostIsRefusedAndShownCut) {
  const auto config = ParseGyroSimConfig(
      "[omega]\nmodbus_host = \"" + std::string(1'000'000, 'h') + "\"\n", "sim.toml");
  ASSERT_FALSE(config.has_value());
  EXPECT_NE(config.error().ToString().find("sim.toml:2: key 'omega.modbus_host' = \"hhhh"),
            std::string::npos);
  EXPECT_NE(config.error().ToString().find("a name has at most 255"), std::string::npos);
  EXPECT_LT(config.error().ToString().size(), 200u) << config.error().ToString().substr(0, 200);
}

TEST(GyroSimConfigBounds, ExciteTimeOf1e12SecondsIsRefused) {
  const auto config = ParseGyroSimConfig("[electronics]\nexcite_time_s = 1e12\n", "sim.toml");
  ASSERT_FALSE(config.has_value());
  EXPECT_NE(config.error().ToString().find(
                "key 'electronics.excite_time_s' = 1e12: out of range: must be in [0, 600]"),
            std::string::npos)
      << config.error().ToString();
}

}  // namespace
}  // namespace hrgbench::drivers::sim
