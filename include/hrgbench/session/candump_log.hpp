#pragma once
// Raw CAN frames in candump log format (`candump -L`), one frame a line, readable by can-utils'
// canplayer and log2asc and by python-can's CanutilsLogReader:
//   (1700000000.123456) can0 123#DEADBEEF          classic, standard id: 3 hex digits
//   (1700000000.123456) can0 1ABCDEF0#00           extended id: 8 hex digits
//   (1700000000.123456) can0 123#R  / 123#R4       remote frame (length printed when 1..8)
//   (1700000000.123456) can0 123##1DEADBEEF        CAN FD: '##', flags nibble (1 = BRS), data
//   (1700000000.123456) can0 20000080#0000000000000000
//                                                  error frame: CAN_ERR_FLAG (0x20000000) | class
//                                                  bits, 8 hex digits, the 8 data bytes
// as can-utils lib.c sprint_canframe() writes them (upper-case hex, no separators) behind
// "(%010lu.%06lu) <ifname> ". Error frames are always classic (CAN_ERR_DLC 8 bytes shown, or the
// frame's length if shorter); remote frames of FD frames do not exist.
//
// The frame part is the hardware layer's one can-utils formatter, hw::FormatCanFrame
// (hrgbench/hw/can_frame_text.hpp); this file adds the time stamp, interface and line framing.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <expected>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hrgbench/hw/can_frame.hpp"
#include "hrgbench/hw/can_frame_text.hpp"
#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench {

namespace internal {
class AppendFile;
}

// A frame and its receive (or send) time. The log needs wall-clock time: `unix_time_ns` is ns since
// the Unix epoch (SocketCAN software stamps are already CLOCK_REALTIME; a monotonic stamp needs the
// caller's offset). Negative times are written as 0.
struct LoggedCanFrame {
  std::int64_t unix_time_ns = 0;
  hw::CanFrame frame;
};

// Longest line FormatCandumpLine writes, interface names up to 15 characters (IFNAMSIZ - 1):
// "(" 20 digits "." 6 digits ") " ifname " " frame text (8 + 2 + 1 + 128) "\n" NUL.
inline constexpr std::size_t kMaxCandumpLineLength =
    1 + 20 + 1 + 6 + 2 + 15 + 1 + (hw::kMaxCanFrameTextLength - 1) + 1 + 1;

// Writes one log line (with '\n') and a NUL into `out`; returns its length without the NUL, or 0
// when `out` is too small or `interface_name` is empty, longer than 15 characters or contains a
// blank. The id is masked to 11/29 bits; the length is clamped to 8 (classic) or 64 (FD).
// Real-time safe: no allocation, no system call; noexcept.
std::size_t FormatCandumpLine(const LoggedCanFrame& logged, std::string_view interface_name,
                              std::span<char> out) noexcept;

struct CandumpLogOptions {
  std::string interface_name = "can0";
  // Buffered bytes are written out (write(2), no fsync) at least this often when Append() is
  // called, so a kill -9 loses at most this much of the log; Sync() makes it durable.
  std::int64_t flush_interval_ns = 200'000'000;
  // Append to an existing log (resume) instead of refusing it. A torn last line (a crash mid-line)
  // is cut off first, so the file stays parseable.
  bool append = false;
};

// Appends frames to a candump log. Not thread-safe and not real-time safe (it formats, buffers and
// calls write(2)/fsync(2)): call it from a non-real-time thread that drains the capture's queue
// (the capture thread itself only enqueues). Never throws (except std::bad_alloc from Open).
class CandumpLogWriter {
 public:
  CandumpLogWriter();
  ~CandumpLogWriter();  // flushes (no fsync) and closes; errors are dropped: call Close() to see
                        // them
  CandumpLogWriter(CandumpLogWriter&&) noexcept;
  CandumpLogWriter& operator=(CandumpLogWriter&&) noexcept;

  // Creates `path` (its directory must exist), or opens it for appending when options.append.
  // Refuses an existing file without options.append (kInvalidArgument), an invalid interface name.
  static std::expected<CandumpLogWriter, RecordError> Open(const std::filesystem::path& path,
                                                           const CandumpLogOptions& options = {});

  // Formats and buffers the frames; writes the buffer out when it is large or the flush interval
  // has passed. After an I/O error every later call returns that error (the file keeps what was
  // written before it).
  std::expected<void, RecordError> Append(std::span<const LoggedCanFrame> frames);
  std::expected<void, RecordError> Flush();  // write(2) the buffer
  std::expected<void, RecordError> Sync();   // Flush, then fsync: durable (call at run end)
  std::expected<void, RecordError> Close();  // Sync and close; further calls are kWrongState

  bool is_open() const noexcept;
  std::uint64_t frames_written() const noexcept { return frames_written_; }
  const std::filesystem::path& path() const noexcept { return path_; }

 private:
  std::unique_ptr<internal::AppendFile> file_;
  std::filesystem::path path_;
  std::string interface_name_;
  std::uint64_t frames_written_ = 0;
};

// Where a log stops being readable: the 1-based line and what is wrong with it. Everything before
// that line was read.
struct CandumpLogDamage {
  std::uint64_t line = 0;
  std::string message;  // "line 1234: no frame text after the interface name: '(17000..."
};

// Bounds on what the reader accepts. A production session is ~1e6 frames; the defaults are far
// above any session the bench records and far below what would exhaust memory or time.
struct CandumpLogReadLimits {
  std::uint64_t max_bytes = std::uint64_t{8} << 30;  // 8 GiB, ~1.3e8 lines
  std::uint64_t max_frames = 200'000'000;
};

// Reads a candump -L log one frame at a time (constant memory: a 1 MiB read buffer), in the
// notation FormatCandumpLine writes and can-utils' candump -L, canplayer and python-can's
// CanutilsLogWriter write. Error frames (CAN_ERR_FLAG set) are counted and skipped: they are
// events of the controller, not traffic a driver receives. Every line must name the same
// interface as the first.
//
// Damage: a line that is not a log line (bad time stamp, missing interface, bad frame text, too
// long), a last line without its end of line (a torn write) or a file past a limit ends the
// reading. Next() then returns nullopt and damage() says which line and why; frames before it
// were all returned. A log that ends cleanly has no damage.
//
// Not thread-safe. Throws nothing but std::bad_alloc.
class CandumpLogReader {
 public:
  CandumpLogReader();
  ~CandumpLogReader();
  CandumpLogReader(CandumpLogReader&&) noexcept;
  CandumpLogReader& operator=(CandumpLogReader&&) noexcept;

  // Opens `path`. kIo when it cannot be opened or is not a regular file; kInvalidArgument when
  // it is larger than limits.max_bytes.
  static std::expected<CandumpLogReader, RecordError> Open(const std::filesystem::path& path,
                                                           const CandumpLogReadLimits& limits = {});

  // The next frame, or nullopt at the end of the log or at its damage.
  std::optional<LoggedCanFrame> Next();

  const std::optional<CandumpLogDamage>& damage() const noexcept { return damage_; }
  std::uint64_t lines_read() const noexcept { return line_; }  // good lines, error frames too
  std::uint64_t frames_read() const noexcept { return frames_; }
  std::uint64_t error_frames() const noexcept { return error_frames_; }
  const std::string& interface_name() const noexcept { return interface_name_; }
  const std::filesystem::path& path() const noexcept { return path_; }

 private:
  // The next line without its '\n' in line_text_; false at the end of the file or damage.
  bool ReadLine();
  void Damage(std::string message);

  std::FILE* file_ = nullptr;
  std::filesystem::path path_;
  CandumpLogReadLimits limits_;
  std::vector<char> buffer_;
  std::size_t buffer_begin_ = 0;
  std::size_t buffer_end_ = 0;
  bool eof_ = false;
  std::string line_text_;
  std::uint64_t line_ = 0;
  std::uint64_t frames_ = 0;
  std::uint64_t error_frames_ = 0;
  std::string interface_name_;
  std::optional<CandumpLogDamage> damage_;
};

// One log line (without '\n') parsed: the frame and the interface name, or why it is not a log
// line. Error frames parse (frame.error set, id = the class bits).
struct CandumpLine {
  LoggedCanFrame logged;
  std::string_view interface_name;  // a view into the line
};
std::expected<CandumpLine, std::string> ParseCandumpLine(std::string_view line);

}  // namespace hrgbench::bench
