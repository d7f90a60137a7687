#pragma once
// ConfigError: what is wrong with a config file (STYLE rule 10: every error names file, line, key
// and value). One type for every TOML file the project reads (station, sequence, limits, simulation
// specs, hrg-gyro-sim's config), so the tools print them the same way and a test can check each
// part.
//
// Loaders stop at the first error: a user fixes one line at a time, and a later error may be a
// consequence of an earlier one.

#include <cstddef>
#include <filesystem>
#include <string>

namespace hrgbench::config_file {

struct ConfigError {
  std::filesystem::path file;
  std::size_t line = 0;  // 1-based; 0 when not about a line (file unreadable, cross-file check)
  std::string key;      // dotted path ("table.port", "runs[2].free_run_s"); empty for syntax errors
  std::string value;    // the offending value exactly as written in the file; empty when missing
  std::string message;  // what is wrong and what is expected

  // "<file>:<line>: key '<key>' = <value>: <message>" (parts omitted when empty or 0).
  std::string ToString() const;
};

}  // namespace hrgbench::config_file
