#pragma once
// The current UTC time as the records write it: "2026-11-27T10:21:31Z" (ISO 8601, seconds).

#include <string>

namespace hrgbench::app {

std::string UtcNowText();

}  // namespace hrgbench::app
