// candump -L log reading: "(SECONDS.MICROS) IFNAME FRAME", the line FormatCandumpLine writes and
// can-utils' candump.c prints. Lines are taken from a fixed read buffer, so a log of any size is
// read in constant memory, and a line longer than any valid one is damage, not an allocation.

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <system_error>
#include <utility>

#include "hrgbench/hw/can_frame_text.hpp"
#include "hrgbench/session/candump_log.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kReadBufferBytes = std::size_t{1} << 20;
constexpr std::uint32_t kCanErrFlag = 0x20000000u;  // linux/can.h CAN_ERR_FLAG
// The longest line any writer of this notation produces (a 64-byte FD frame, a 15-character
// interface, a 20-digit second count); longer is not a log line.
constexpr std::size_t kMaxLineLength = kMaxCandumpLineLength;

// The start of a line for a message, printable and short.
std::string Excerpt(std::string_view line) {
  std::string out;
  for (const char c : line.substr(0, 48)) {
    out += (c >= 0x20 && c < 0x7F) ? c : '?';
  }
  if (line.size() > 48) out += "...";
  return out;
}

bool AllDigits(std::string_view text) {
  if (text.empty()) return false;
  for (const char c : text) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

}  // namespace

std::expected<CandumpLine, std::string> ParseCandumpLine(std::string_view line) {
  // "(" seconds "." micros ")"
  if (line.empty() || line.front() != '(') return std::unexpected("no '(' time stamp");
  const std::size_t close = line.find(')');
  if (close == std::string_view::npos) return std::unexpected("time stamp has no ')'");
  const std::string_view stamp = line.substr(1, close - 1);
  const std::size_t dot = stamp.find('.');
  if (dot == std::string_view::npos) return std::unexpected("time stamp has no '.'");
  const std::string_view seconds_text = stamp.substr(0, dot);
  const std::string_view micros_text = stamp.substr(dot + 1);
  // candump writes 6 fractional digits; seconds fit in int64 ns up to year 2262.
  if (!AllDigits(seconds_text) || seconds_text.size() > 10 || micros_text.size() != 6 ||
      !AllDigits(micros_text)) {
    return std::unexpected("time stamp '" + std::string(stamp) +
                           "' is not SECONDS.MICROSECONDS (at most 10 digits . 6 digits)");
  }
  std::uint64_t seconds = 0;
  std::uint64_t micros = 0;
  std::from_chars(seconds_text.data(), seconds_text.data() + seconds_text.size(), seconds);
  std::from_chars(micros_text.data(), micros_text.data() + micros_text.size(), micros);

  std::string_view rest = line.substr(close + 1);
  if (rest.empty() || rest.front() != ' ') return std::unexpected("no blank after the time stamp");
  rest.remove_prefix(1);
  const std::size_t blank = rest.find(' ');
  if (blank == std::string_view::npos || blank == 0)
    return std::unexpected("no frame text after the interface name");
  const std::string_view interface_name = rest.substr(0, blank);
  if (interface_name.size() > 15)
    return std::unexpected("interface name longer than 15 characters");
  const std::string_view text = rest.substr(blank + 1);

  CandumpLine parsed;
  parsed.interface_name = interface_name;
  parsed.logged.unix_time_ns =
      static_cast<std::int64_t>(seconds * 1'000'000'000ull + micros * 1000ull);
  // An error frame's id carries CAN_ERR_FLAG, which the frame notation's parser refuses (it only
  // reads frames a bus carries): read it with the flag taken off.
  const std::size_t hash = text.find('#');
  if (hash == 8 && text.size() > 9 && text[9] != '#') {
    std::uint32_t id = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + 8, id, 16);
    if (ec == std::errc() && end == text.data() + 8 && (id & kCanErrFlag) != 0) {
      static constexpr char kHex[] = "0123456789ABCDEF";
      std::string without_flag(8, '0');
      const std::uint32_t bits = id & ~kCanErrFlag;
      for (int i = 0; i < 8; ++i) without_flag[7 - i] = kHex[(bits >> (4 * i)) & 0xF];
      auto frame = hw::ParseCanFrame(without_flag + std::string(text.substr(8)));
      if (!frame || frame->fd || frame->remote)
        return std::unexpected("error frame text '" + std::string(text) + "' does not parse");
      frame->error = true;
      frame->extended = false;
      parsed.logged.frame = *frame;
      return parsed;
    }
  }
  auto frame = hw::ParseCanFrame(text);
  if (!frame) return std::unexpected("frame text '" + std::string(text) + "' does not parse");
  parsed.logged.frame = *frame;
  return parsed;
}

CandumpLogReader::CandumpLogReader() = default;

CandumpLogReader::~CandumpLogReader() {
  if (file_ != nullptr) std::fclose(file_);
}

CandumpLogReader::CandumpLogReader(CandumpLogReader&& other) noexcept
    : file_(std::exchange(other.file_, nullptr)),
      path_(std::move(other.path_)),
      limits_(other.limits_),
      buffer_(std::move(other.buffer_)),
      buffer_begin_(other.buffer_begin_),
      buffer_end_(other.buffer_end_),
      eof_(other.eof_),
      line_text_(std::move(other.line_text_)),
      line_(other.line_),
      frames_(other.frames_),
      error_frames_(other.error_frames_),
      interface_name_(std::move(other.interface_name_)),
      damage_(std::move(other.damage_)) {}

CandumpLogReader& CandumpLogReader::operator=(CandumpLogReader&& other) noexcept {
  if (this != &other) {
    if (file_ != nullptr) std::fclose(file_);
    file_ = std::exchange(other.file_, nullptr);
    path_ = std::move(other.path_);
    limits_ = other.limits_;
    buffer_ = std::move(other.buffer_);
    buffer_begin_ = other.buffer_begin_;
    buffer_end_ = other.buffer_end_;
    eof_ = other.eof_;
    line_text_ = std::move(other.line_text_);
    line_ = other.line_;
    frames_ = other.frames_;
    error_frames_ = other.error_frames_;
    interface_name_ = std::move(other.interface_name_);
    damage_ = std::move(other.damage_);
  }
  return *this;
}

std::expected<CandumpLogReader, RecordError> CandumpLogReader::Open(
    const fs::path& path, const CandumpLogReadLimits& limits) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::is_regular_file(status)) {
    return std::unexpected(RecordError{RecordErrorKind::kIo, path,
                                       ec ? "cannot read the CAN log: " + ec.message()
                                          : std::string("the CAN log is not a regular file")});
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > limits.max_bytes) {
    return std::unexpected(RecordError{RecordErrorKind::kInvalidArgument, path,
                                       "the CAN log is " + std::to_string(size) +
                                           " bytes (at most " + std::to_string(limits.max_bytes) +
                                           ")"});
  }
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    return std::unexpected(
        RecordError{RecordErrorKind::kIo, path,
                    std::string("cannot open the CAN log: ") + std::strerror(errno)});
  }
  CandumpLogReader reader;
  reader.file_ = file;
  reader.path_ = path;
  reader.limits_ = limits;
  reader.buffer_.resize(kReadBufferBytes);
  return reader;
}

void CandumpLogReader::Damage(std::string message) {
  damage_ = CandumpLogDamage{line_ + 1, "line " + std::to_string(line_ + 1) + ": " + message};
}

bool CandumpLogReader::ReadLine() {
  line_text_.clear();
  for (;;) {
    const char* begin = buffer_.data() + buffer_begin_;
    const std::size_t available = buffer_end_ - buffer_begin_;
    const void* newline = std::memchr(begin, '\n', available);
    const std::size_t take =
        newline != nullptr ? static_cast<std::size_t>(static_cast<const char*>(newline) - begin)
                           : available;
    if (line_text_.size() + take > kMaxLineLength) {
      line_text_.append(begin, std::min(take, std::size_t{64}));
      Damage("longer than any log line (" + std::to_string(kMaxLineLength) + " characters): '" +
             Excerpt(line_text_) + "'");
      return false;
    }
    line_text_.append(begin, take);
    if (newline != nullptr) {
      buffer_begin_ += take + 1;
      return true;
    }
    buffer_begin_ = buffer_end_ = 0;
    if (eof_) {
      if (!line_text_.empty()) {
        Damage("cut off (no end of line; the writer stopped mid-line): '" + Excerpt(line_text_) +
               "'");
      }
      return false;
    }
    const std::size_t got = std::fread(buffer_.data(), 1, buffer_.size(), file_);
    if (got < buffer_.size()) {
      if (std::ferror(file_) != 0) {
        Damage(std::string("read error: ") + std::strerror(errno));
        return false;
      }
      eof_ = true;
    }
    buffer_end_ = got;
  }
}

std::optional<LoggedCanFrame> CandumpLogReader::Next() {
  while (!damage_ && file_ != nullptr) {
    if (!ReadLine()) return std::nullopt;
    if (frames_ + error_frames_ >= limits_.max_frames) {
      Damage("more than " + std::to_string(limits_.max_frames) + " frames");
      return std::nullopt;
    }
    auto parsed = ParseCandumpLine(line_text_);
    if (!parsed) {
      Damage(parsed.error() + ": '" + Excerpt(line_text_) + "'");
      return std::nullopt;
    }
    if (interface_name_.empty()) {
      interface_name_ = std::string(parsed->interface_name);
    } else if (parsed->interface_name != interface_name_) {
      Damage("interface '" + std::string(parsed->interface_name) + "', the log's is '" +
             interface_name_ + "'");
      return std::nullopt;
    }
    ++line_;
    if (parsed->logged.frame.error) {
      ++error_frames_;
      continue;
    }
    ++frames_;
    return parsed->logged;
  }
  return std::nullopt;
}

}  // namespace hrgbench::bench
