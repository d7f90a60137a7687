#include "append_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>

#include "hrgbench/session/session.hpp"

namespace hrgbench::bench::internal {

namespace fs = std::filesystem;

std::unexpected<RecordError> IoError(const fs::path& file, std::string_view what,
                                     int error_number) {
  return std::unexpected(RecordError{RecordErrorKind::kIo, file,
                                     std::string(what) + ": " + std::strerror(error_number)});
}

namespace {

// The session library owns the durable directory operations; the recorder reports in its own error
// type.
std::expected<void, RecordError> FromSession(std::expected<void, session::SessionError> result) {
  if (result) return {};
  return std::unexpected(
      RecordError{RecordErrorKind::kIo, result.error().file, result.error().message});
}

}  // namespace

std::expected<void, RecordError> FsyncDirectory(const fs::path& dir) {
  return FromSession(session::FsyncDirectory(dir));
}

std::expected<void, RecordError> MakeDirectoryDurably(const fs::path& dir) {
  return FromSession(session::CreateDirectoriesDurably(dir));
}

std::expected<void, RecordError> RenameDurably(const fs::path& from, const fs::path& to) {
  if (::rename(from.c_str(), to.c_str()) != 0) {
    return IoError(to, "cannot rename " + from.filename().string() + " into place", errno);
  }
  return FsyncDirectory(to.parent_path());
}

std::expected<void, RecordError> TrimToLastNewline(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return {};
    return IoError(path, "cannot open", errno);
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int error_number = errno;
    ::close(fd);
    return IoError(path, "cannot stat", error_number);
  }
  // Scan backwards in blocks for the last '\n'.
  off_t end = st.st_size;
  off_t keep = 0;
  char block[4096];
  while (end > 0 && keep == 0) {
    const off_t start = end > static_cast<off_t>(sizeof block) ? end - sizeof block : 0;
    const ssize_t n = ::pread(fd, block, static_cast<std::size_t>(end - start), start);
    if (n < 0) {
      const int error_number = errno;
      ::close(fd);
      return IoError(path, "cannot read", error_number);
    }
    for (ssize_t i = n - 1; i >= 0; --i) {
      if (block[i] == '\n') {
        keep = start + i + 1;
        break;
      }
    }
    end = start;
  }
  std::expected<void, RecordError> result;
  if (keep != st.st_size) {
    if (::ftruncate(fd, keep) != 0 || ::fsync(fd) != 0)
      result = IoError(path, "cannot trim", errno);
  }
  ::close(fd);
  return result;
}

std::int64_t MonotonicNs() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

AppendFile::AppendFile(fs::path path, int fd, std::int64_t flush_interval_ns)
    : path_(std::move(path)),
      fd_(fd),
      flush_interval_ns_(flush_interval_ns),
      last_flush_ns_(MonotonicNs()) {
  buffer_.reserve(kFlushBytes + 64 * 1024);
}

std::expected<std::unique_ptr<AppendFile>, RecordError> AppendFile::Open(
    const fs::path& path, Mode mode, std::int64_t flush_interval_ns) {
  const int flags =
      O_WRONLY | O_CLOEXEC | O_APPEND | (mode == Mode::kCreateNew ? O_CREAT | O_EXCL : O_CREAT);
  const int fd = ::open(path.c_str(), flags, 0666);
  if (fd < 0) return IoError(path, "cannot create", errno);
  // A new file's directory entry must survive a power loss as well as its data.
  if (auto synced = FsyncDirectory(path.parent_path()); !synced) {
    ::close(fd);
    return std::unexpected(synced.error());
  }
  return std::unique_ptr<AppendFile>(new AppendFile(path, fd, flush_interval_ns));
}

AppendFile::~AppendFile() {
  if (fd_ >= 0) {
    (void)Flush();
    ::close(fd_);
  }
}

std::expected<void, RecordError> AppendFile::MaybeFlush() {
  if (buffer_.size() >= kFlushBytes || MonotonicNs() - last_flush_ns_ >= flush_interval_ns_) {
    return Flush();
  }
  return {};
}

std::expected<void, RecordError> AppendFile::Flush() {
  if (failure_) return std::unexpected(*failure_);
  if (fd_ < 0) return std::unexpected(RecordError{RecordErrorKind::kWrongState, path_, "closed"});
  const char* data = buffer_.data();
  std::size_t remaining = buffer_.size();
  while (remaining > 0) {
    const ssize_t n = ::write(fd_, data, remaining);
    if (n < 0) {
      if (errno == EINTR) continue;
      // Keep what did not go out: the caller may want to know how much is lost, and a later
      // Flush must not write a line twice.
      buffer_.erase(0, buffer_.size() - remaining);
      failure_ = IoError(path_, "cannot write", errno).error();
      return std::unexpected(*failure_);
    }
    data += n;
    remaining -= static_cast<std::size_t>(n);
    bytes_written_ += static_cast<std::uint64_t>(n);
  }
  buffer_.clear();
  last_flush_ns_ = MonotonicNs();
  return {};
}

std::expected<void, RecordError> AppendFile::Sync() {
  if (auto flushed = Flush(); !flushed) return flushed;
  if (::fsync(fd_) != 0) {
    failure_ = IoError(path_, "cannot fsync", errno).error();
    return std::unexpected(*failure_);
  }
  return {};
}

std::expected<void, RecordError> AppendFile::Close() {
  if (fd_ < 0) return {};
  auto synced = Sync();
  // close() can report a deferred write error (NFS); it counts.
  if (::close(fd_) != 0 && synced) synced = IoError(path_, "cannot close", errno);
  fd_ = -1;
  return synced;
}

void AppendFile::Abandon() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  buffer_.clear();
}

}  // namespace hrgbench::bench::internal
