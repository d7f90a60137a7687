#pragma once
// Where a new session goes when the operator does not say: SERIAL-YYYYMMDDTHHMMSSZ (UTC) directly
// in the sessions folder, with -2 … -99 appended when a folder of that name exists (two sessions of
// one unit within a second). One rule for `hrg-bench run` without -o and for the panel's Start.

#include <ctime>
#include <expected>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::app {

// The folder for a session of `serial` started at `now`; error when the serial is refused
// (serial_check.hpp) or none of the names is free (the message names the sessions folder).
// Creates nothing.
std::expected<std::filesystem::path, std::string> NewSessionFolder(
    const std::filesystem::path& sessions_dir, std::string_view serial, std::time_t now);

// Why `dir` cannot be resumed because no session started in it: it does not exist, or holds
// neither session.json nor fixture.json (a kill before the record was written: nothing was run).
// The message says what to do. std::nullopt when it holds a record.
std::optional<std::string> NotStartedProblem(const std::filesystem::path& dir);

}  // namespace hrgbench::app
