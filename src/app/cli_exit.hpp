#pragma once
// What every tool's main shares: the exit-code table (hrgbench/session/exit_codes.hpp, printed by
// each --help), the command-line parse and the catch-all.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <string>

#include "hrgbench/session/exit_codes.hpp"
#include "logging.hpp"

namespace hrgbench::app {

// CLI11's parse outcome as our exit code: --help/--version print and exit 0, a bad command line
// prints CLI11's message and exits kExitBadInput.
inline int ExitForParseError(const CLI::App& app, const CLI::ParseError& error) {
  const int cli_code = app.exit(error);
  return cli_code == 0 ? kExitOk : kExitBadInput;
}

// Adds the flags every tool has: -q/--quiet and --version.
inline void AddCommonFlags(CLI::App& app, bool* quiet) {
  app.add_flag("-q,--quiet", *quiet, "log warnings and errors only");
  app.set_version_flag("--version", HRGBENCH_SOFTWARE_VERSION);
}

// The body of every tool's main(): parse the command line, set up logging on stderr, run `body`.
// Only main catches everything: an exception that escapes the tool is logged and is kExitError.
template <typename Body>
int ParseAndRun(CLI::App& app, int argc, char** argv, const std::string& tool, const bool& quiet,
                Body body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return ExitForParseError(app, error);
  }
  SetUpStderrLogging(tool, quiet ? -1 : 0);
  try {
    return body();
  } catch (const std::exception& error) {
    spdlog::critical("unexpected failure: {}", error.what());
    return kExitError;
  }
}

}  // namespace hrgbench::app
