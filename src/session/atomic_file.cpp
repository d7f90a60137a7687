#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "hrgbench/session/kill_point.hpp"
#include "hrgbench/session/session.hpp"

namespace hrgbench::session {
namespace {

namespace fs = std::filesystem;

std::unexpected<SessionError> SystemError(const fs::path& file, const std::string& what,
                                          int error_number) {
  return std::unexpected(SessionError{file, 0, "", what + ": " + std::strerror(error_number)});
}

fs::path ParentOrDot(const fs::path& path) {
  fs::path parent = path.parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

std::expected<void, SessionError> WriteAll(int fd, const std::string& contents,
                                           const fs::path& file) {
  const char* data = contents.data();
  std::size_t remaining = contents.size();
  while (remaining > 0) {
    const ssize_t n = ::write(fd, data, remaining);
    if (n < 0) {
      if (errno == EINTR) continue;
      return SystemError(file, "cannot write", errno);
    }
    data += n;
    remaining -= static_cast<std::size_t>(n);
  }
  return {};
}

}  // namespace

std::expected<void, SessionError> FsyncDirectory(const fs::path& dir) {
  const fs::path target = dir.empty() ? fs::path(".") : dir;
  const int fd = ::open(target.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return SystemError(target, "cannot open directory for fsync", errno);
  if (::fsync(fd) != 0) {
    const int error_number = errno;
    ::close(fd);
    return SystemError(target, "cannot fsync directory", error_number);
  }
  ::close(fd);
  return {};
}

std::expected<void, SessionError> CreateDirectoriesDurably(const fs::path& dir) {
  if (dir.empty()) return {};
  std::vector<fs::path> missing;  // deepest first
  std::error_code ec;
  for (fs::path p = dir; !p.empty(); p = p.parent_path()) {
    if (fs::exists(p, ec)) break;
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST) {
      return SystemError(*it, "cannot create directory", errno);
    }
    if (auto synced = FsyncDirectory(ParentOrDot(*it)); !synced) return synced;
  }
  if (!fs::is_directory(dir, ec)) {
    return std::unexpected(SessionError{dir, 0, "", "exists and is not a directory"});
  }
  return {};
}

std::expected<void, SessionError> WriteFileAtomic(const fs::path& path,
                                                  const std::string& contents) {
  // Unique per process and call, so concurrent writers of the same file never share a temporary.
  static std::atomic<std::uint64_t> counter{0};
  const fs::path dir = ParentOrDot(path);
  const fs::path temp =
      dir / ("." + path.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
             std::to_string(counter.fetch_add(1)));

  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return SystemError(path, "cannot create temporary " + temp.string(), errno);
  auto result = WriteAll(fd, contents, path);
  if (result && ::fsync(fd) != 0) result = SystemError(path, "cannot fsync", errno);
  // close() can report a deferred write error (NFS); it counts.
  if (::close(fd) != 0 && result) result = SystemError(path, "cannot close", errno);
  if (result) KillPoint("atomic.written");
  if (result && ::rename(temp.c_str(), path.c_str()) != 0) {
    result = SystemError(path, "cannot rename temporary into place", errno);
  }
  if (!result) {
    ::unlink(temp.c_str());
    return result;
  }
  return FsyncDirectory(dir);
}

}  // namespace hrgbench::session
