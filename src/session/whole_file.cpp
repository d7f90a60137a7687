#include "whole_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace hrgbench::session::internal {

std::expected<std::string, SessionError> ReadWholeFile(const std::filesystem::path& path) {
  auto fail = [&path](const char* what) {
    return std::unexpected(
        SessionError{path, 0, "", std::string(what) + ": " + std::strerror(errno)});
  };
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return fail("cannot open");
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const auto error = fail("cannot stat");
    ::close(fd);
    return error;
  }
  // st_size is only a hint (the file may grow while we read); read until EOF.
  std::string data;
  data.resize(st.st_size > 0 ? static_cast<std::size_t>(st.st_size) + 1 : 4096);
  std::size_t used = 0;
  for (;;) {
    if (used == data.size()) data.resize(data.size() * 2);
    const ssize_t n = ::read(fd, data.data() + used, data.size() - used);
    if (n < 0) {
      if (errno == EINTR) continue;
      const auto error = fail("cannot read");
      ::close(fd);
      return error;
    }
    if (n == 0) break;
    used += static_cast<std::size_t>(n);
  }
  ::close(fd);
  data.resize(used);
  return data;
}

}  // namespace hrgbench::session::internal
