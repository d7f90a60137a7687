#pragma once
// Exit codes shared by the tools (documented in each --help).

#include <exception>
#include <string>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "logging.hpp"

namespace hrgbench::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitNotUsable = 1;  // ran, but the result is not usable (see the message)
inline constexpr int kExitBadInput = 2;   // bad command line, config or session; nothing written

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
// Only main catches everything: an exception that escapes the tool is logged and is kExitNotUsable.
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
    return kExitNotUsable;
  }
}

}  // namespace hrgbench::app
