#pragma once
// Internal: read a whole file into memory in one go (the CSV parser works on the buffer).

#include <cstddef>
#include <expected>
#include <filesystem>
#include <string>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session::internal {

// The file's bytes, or an error (line 0, no field): the system's reason when it cannot be opened
// or read, "is a directory, not a file", "not a regular file" (a FIFO or a device could block or
// never end), or "file too large" beyond `max_bytes` (checked on the size before reading, and
// again while reading, since the file may grow).
std::expected<std::string, SessionError> ReadWholeFile(const std::filesystem::path& path,
                                                       std::size_t max_bytes);

}  // namespace hrgbench::session::internal
