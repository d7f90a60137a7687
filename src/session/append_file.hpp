#pragma once
// Internal: a buffered append-only file (the streamed run CSV, the CAN log) and the few durable
// directory operations the recorder needs beyond session::WriteFileAtomic.
// FsyncDirectory and MakeDirectoryDurably are the session library's, in the recorder's error type.

#include <cstdint>
#include <expected>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench::internal {

// kIo error "<what>: <strerror(error_number)>" about `file`.
std::unexpected<RecordError> IoError(const std::filesystem::path& file, std::string_view what,
                                     int error_number);

// fsync of a directory, so renames and creations in it survive a power loss.
std::expected<void, RecordError> FsyncDirectory(const std::filesystem::path& dir);

// mkdir -p, fsyncing the parent of every directory it created.
std::expected<void, RecordError> MakeDirectoryDurably(const std::filesystem::path& dir);

// rename(2) then fsync of the destination's directory (same directory for both here).
std::expected<void, RecordError> RenameDurably(const std::filesystem::path& from,
                                               const std::filesystem::path& to);

// Cuts a file after its last '\n' (a line torn by a crash); an empty or absent file is left alone.
std::expected<void, RecordError> TrimToLastNewline(const std::filesystem::path& path);

// Monotonic ns (steady clock), for flush intervals.
std::int64_t MonotonicNs() noexcept;

class AppendFile {
 public:
  enum class Mode { kCreateNew, kAppend };
  // Bytes buffered before a write(2) regardless of the interval.
  static constexpr std::size_t kFlushBytes = std::size_t{1} << 20;

  static std::expected<std::unique_ptr<AppendFile>, RecordError> Open(
      const std::filesystem::path& path, Mode mode, std::int64_t flush_interval_ns);
  ~AppendFile();  // writes the buffer out (errors dropped) and closes
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;

  // Append text here, then call MaybeFlush().
  std::string& buffer() noexcept { return buffer_; }
  // Writes the buffer out if it is large or the flush interval has passed.
  std::expected<void, RecordError> MaybeFlush();
  std::expected<void, RecordError> Flush();
  std::expected<void, RecordError> Sync();   // Flush + fsync
  std::expected<void, RecordError> Close();  // Sync + close (idempotent)
  // Closes without writing the buffer (after a failure, or to abandon the file).
  void Abandon() noexcept;

  const std::filesystem::path& path() const noexcept { return path_; }
  bool is_open() const noexcept { return fd_ >= 0; }
  std::uint64_t bytes_written() const noexcept { return bytes_written_; }

 private:
  AppendFile(std::filesystem::path path, int fd, std::int64_t flush_interval_ns);

  std::filesystem::path path_;
  int fd_ = -1;
  std::int64_t flush_interval_ns_ = 0;
  std::int64_t last_flush_ns_ = 0;
  std::uint64_t bytes_written_ = 0;
  std::string buffer_;
  std::optional<RecordError> failure_;  // sticky: the first I/O error
};

}  // namespace hrgbench::bench::internal
