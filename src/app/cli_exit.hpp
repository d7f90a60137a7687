#pragma once
// Exit codes shared by the tools (documented in each --help).

#include <CLI/CLI.hpp>

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

}  // namespace hrgbench::app
