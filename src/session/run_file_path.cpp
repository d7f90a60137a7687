#include "run_file_path.hpp"

#include <filesystem>

namespace hrgbench::session::internal {

std::optional<std::string> RunFilePathProblem(std::string_view file) {
  if (file.empty()) return "empty file name";
  const std::filesystem::path path(file);
  if (path.has_root_path()) return "absolute path '" + std::string(file) + "' (must be relative)";
  const std::filesystem::path normal = path.lexically_normal();
  if (normal.empty() || normal == "." || *normal.begin() == "..") {
    return "'" + std::string(file) + "' is outside the session directory";
  }
  if (!normal.has_filename()) return "'" + std::string(file) + "' names a directory";
  return std::nullopt;
}

}  // namespace hrgbench::session::internal
