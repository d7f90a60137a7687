#pragma once
// A unit serial (or an operator id), from the operator panel or `hrg-bench run --serial`, checked
// before it becomes part of a folder name or the record.
//
// Accepted: 1..64 characters, letters, digits and . _ - only, starting with a letter or digit, and
// no "..": a serial can then never name a parent folder, a hidden file, an option or anything
// outside the sessions folder, whatever the file system. It is also checked as the config files
// check a name (config_file::StringProblem, StringKind::kName), so the panel and the configs agree.
// Pure function.

#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::app {

inline constexpr std::size_t kMaxSerialLength = 64;

// Why `serial` is refused (a sentence for the operator, never echoing more than 32 characters of
// it), or nullopt when it is accepted.
std::optional<std::string> SerialProblem(std::string_view serial);

// An operator id (`hrg-bench run --operator`, the panel's operator field: typed or scanned from a
// badge), by the same rule: it is recorded in session.json and the results store.
std::optional<std::string> OperatorProblem(std::string_view operator_id);

}  // namespace hrgbench::app
