#pragma once
// Internal: the rule for runs[].file, shared by reader and writer so the writer never produces a
// session the reader refuses.

#include <optional>
#include <string>
#include <string_view>

namespace hrgbench::session::internal {

// Why `file` is not an acceptable run file name (empty, absolute, or leaving the session directory
// lexically), or nullopt when it is fine.
std::optional<std::string> RunFilePathProblem(std::string_view file);

}  // namespace hrgbench::session::internal
