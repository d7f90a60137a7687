#include "app/session_folder.hpp"

#include "app/serial_check.hpp"

namespace hrgbench::app {

std::expected<std::filesystem::path, std::string> NewSessionFolder(
    const std::filesystem::path& sessions_dir, std::string_view serial, std::time_t now) {
  if (auto problem = SerialProblem(serial)) return std::unexpected("serial: " + *problem);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &utc);
  const std::string name = std::string(serial) + "-" + stamp;
  std::error_code ec;
  for (int i = 1; i < 100; ++i) {
    std::filesystem::path dir = sessions_dir / (i == 1 ? name : name + "-" + std::to_string(i));
    if (!std::filesystem::exists(dir, ec) && !ec) return dir;
  }
  return std::unexpected("no free session folder for " + std::string(serial) + " in " +
                         sessions_dir.string() + " (" + name + " … -99 exist)");
}

std::optional<std::string> NotStartedProblem(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return dir.string() + ": no such session folder";
  if (std::filesystem::exists(dir / "session.json", ec) ||
      std::filesystem::exists(dir / "fixture.json", ec))
    return std::nullopt;
  return dir.string() +
         ": holds neither session.json nor fixture.json: the session was stopped before its "
         "record was written, so nothing was run and there is nothing to resume; remove the "
         "folder and start the session again (hrg-bench run)";
}

}  // namespace hrgbench::app
