#pragma once
// Internal: read a whole file into memory in one go (the CSV parser works on the buffer).

#include <expected>
#include <filesystem>
#include <string>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session::internal {

// The file's bytes, or an error (line 0, no field) with the system's reason.
std::expected<std::string, SessionError> ReadWholeFile(const std::filesystem::path& path);

}  // namespace hrgbench::session::internal
