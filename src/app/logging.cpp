#include "app/logging.hpp"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace hrgbench::app {

void SetUpStderrLogging(const std::string& tool, int verbosity) {
  // Plain (uncoloured) sink: stderr is often a log file or a CI capture.
  auto logger = spdlog::stderr_logger_mt(tool);
  logger->set_pattern("%n: %^%l%$: %v");
  logger->set_level(verbosity < 0   ? spdlog::level::warn
                    : verbosity > 0 ? spdlog::level::debug
                                    : spdlog::level::info);
  spdlog::set_default_logger(logger);
}

}  // namespace hrgbench::app
