#pragma once
// Logs of the tools go to stderr only: stdout carries results (tables, --json) that scripts parse.

#include <string>

namespace hrgbench::app {

// Installs a stderr logger named `tool` as spdlog's default. `verbosity`: -1 quiet (warnings and
// errors), 0 normal (info), 1 debug.
void SetUpStderrLogging(const std::string& tool, int verbosity);

}  // namespace hrgbench::app
