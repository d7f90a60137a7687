#pragma once
// A simulation spec (bench_configs/sim-*.toml): the truth (δ, ξ), the noise (σ, seed) and the runs
// (Ω, orbit at release, sample rate, length). The same file is a valid experiment plan for
// hrg-design, so there is one loader for both (see bench_configs/README.md for every key).
//
// Loading is strict, because a silently ignored key in a plan is a wrong experiment: unknown keys,
// wrong types, out-of-range and missing values are errors, and each error names the file, the line,
// the key (dotted path, "runs[2].sample_rate_hz") and the offending value.

#include <cstddef>
#include <cstdint>
#include <expected>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/config/config_error.hpp"
#include "hrgbench/estimator/parameters.hpp"
#include "hrgbench/estimator/run_data.hpp"

namespace hrgbench::app {

// The project's config error (file, line, key, value, message); see
// hrgbench/config/config_error.hpp.
using ConfigError = config_file::ConfigError;

struct SimSpec {
  std::filesystem::path file;  // where it was loaded from (for messages and provenance)
  std::string description;     // free text, copied into the session
  std::string serial;          // unit serial recorded in the session; default "SIM-<file stem>"
  estimator::Delta delta = estimator::Delta::Zero();
  estimator::Xi xi = estimator::Xi::Zero();
  double sigma = 0.0;  // noise std per channel of y; 0 = noise-free
  std::uint64_t seed = 1;
  std::vector<estimator::RunPlan> runs;

  std::vector<double> Omegas() const;
};

// Largest samples per run a spec may ask for: 1e7 samples are 400 MB of CSV values in memory, far
// beyond any bench run (1 kHz for 1 h is 3.6e6), so more is a typo in a rate or a length.
inline constexpr double kMaxSamplesPerRun = 1e7;

// Loads and validates a spec file.
std::expected<SimSpec, ConfigError> LoadSimSpec(const std::filesystem::path& file);

// The same from text already in memory; `file` is only used in messages and for the serial default.
std::expected<SimSpec, ConfigError> ParseSimSpec(std::string_view toml_text,
                                                 const std::filesystem::path& file);

}  // namespace hrgbench::app
