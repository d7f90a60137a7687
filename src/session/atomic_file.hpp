#pragma once
// Internal: durable directory creation (WriteFileAtomic itself is public).

#include <expected>
#include <filesystem>

#include "hrgbench/session/session.hpp"

namespace hrgbench::session::internal {

// Creates `dir` and its missing ancestors, fsyncing the parent of every directory it created so
// the new entries survive a power loss together with the files later renamed into them.
std::expected<void, SessionError> CreateDirectoriesDurably(const std::filesystem::path& dir);

}  // namespace hrgbench::session::internal
