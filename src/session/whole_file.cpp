#include "whole_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <utility>

namespace hrgbench::session::internal {

std::expected<std::string, SessionError> ReadWholeFile(const std::filesystem::path& path,
                                                       std::size_t max_bytes) {
  auto fail = [&path](const char* what) {
    return std::unexpected(
        SessionError{path, 0, "", std::string(what) + ": " + std::strerror(errno)});
  };
  auto refuse = [&path](std::string what) {
    return std::unexpected(SessionError{path, 0, "", std::move(what)});
  };
  auto too_large = [&refuse, max_bytes](std::size_t bytes, bool at_least) {
    return refuse("file too large: " + std::string(at_least ? "more than " : "") +
                  std::to_string(bytes) + " bytes (at most " + std::to_string(max_bytes) + ")");
  };
  // O_NONBLOCK: opening a FIFO would otherwise wait for a writer (it is refused below).
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return fail("cannot open");
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const auto error = fail("cannot stat");
    ::close(fd);
    return error;
  }
  // Opening a directory read-only succeeds; reading it fails with a less helpful EISDIR.
  if (S_ISDIR(st.st_mode) || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return refuse(S_ISDIR(st.st_mode) ? "is a directory, not a file" : "not a regular file");
  }
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) {
    ::close(fd);
    return too_large(static_cast<std::size_t>(st.st_size), false);
  }
  // st_size is only a hint (the file may grow while we read); read until EOF or past max_bytes.
  // The buffer is grown without being zeroed first (resize_and_overwrite): read() writes every
  // byte that is kept, and zeroing a run CSV's megabytes cost the report an eighth of its time.
  std::string data;
  const auto grow = [&data](std::size_t size) {
    data.resize_and_overwrite(size, [](char*, std::size_t n) { return n; });
  };
  grow(st.st_size > 0 ? static_cast<std::size_t>(st.st_size) + 1 : 4096);
  std::size_t used = 0;
  for (;;) {
    if (used > max_bytes) {
      ::close(fd);
      return too_large(max_bytes, true);
    }
    if (used == data.size()) grow(std::min(data.size() * 2, max_bytes + 1));
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
