#include "hrgbench/session/candump_log.hpp"

#include <system_error>

#include "append_file.hpp"

namespace hrgbench::bench {

namespace fs = std::filesystem;

CandumpLogWriter::CandumpLogWriter() = default;
CandumpLogWriter::~CandumpLogWriter() = default;
CandumpLogWriter::CandumpLogWriter(CandumpLogWriter&&) noexcept = default;
CandumpLogWriter& CandumpLogWriter::operator=(CandumpLogWriter&&) noexcept = default;

std::expected<CandumpLogWriter, RecordError> CandumpLogWriter::Open(
    const fs::path& path, const CandumpLogOptions& options) {
  char probe[kMaxCandumpLineLength];
  if (FormatCandumpLine(LoggedCanFrame{}, options.interface_name, probe) == 0) {
    return std::unexpected(RecordError{RecordErrorKind::kInvalidArgument, path,
                                       "invalid CAN interface name '" + options.interface_name +
                                           "' (1..15 characters, no blanks)"});
  }
  std::error_code ec;
  if (!options.append && fs::exists(path, ec)) {
    return std::unexpected(
        RecordError{RecordErrorKind::kInvalidArgument, path, "CAN log exists already"});
  }
  if (options.append) {
    if (auto trimmed = internal::TrimToLastNewline(path); !trimmed) {
      return std::unexpected(trimmed.error());
    }
  }
  auto file = internal::AppendFile::Open(
      path,
      options.append ? internal::AppendFile::Mode::kAppend : internal::AppendFile::Mode::kCreateNew,
      options.flush_interval_ns);
  if (!file) return std::unexpected(file.error());
  CandumpLogWriter writer;
  writer.file_ = std::move(*file);
  writer.path_ = path;
  writer.interface_name_ = options.interface_name;
  return writer;
}

std::expected<void, RecordError> CandumpLogWriter::Append(std::span<const LoggedCanFrame> frames) {
  if (!is_open()) {
    return std::unexpected(RecordError{RecordErrorKind::kWrongState, path_, "CAN log not open"});
  }
  std::string& buffer = file_->buffer();
  char line[kMaxCandumpLineLength];
  for (const LoggedCanFrame& logged : frames) {
    const std::size_t n = FormatCandumpLine(logged, interface_name_, line);
    buffer.append(line, n);
    ++frames_written_;
    if (buffer.size() >= internal::AppendFile::kFlushBytes) {
      if (auto flushed = file_->Flush(); !flushed) return flushed;
    }
  }
  return file_->MaybeFlush();
}

std::expected<void, RecordError> CandumpLogWriter::Flush() {
  if (!is_open()) {
    return std::unexpected(RecordError{RecordErrorKind::kWrongState, path_, "CAN log not open"});
  }
  return file_->Flush();
}

std::expected<void, RecordError> CandumpLogWriter::Sync() {
  if (!is_open()) {
    return std::unexpected(RecordError{RecordErrorKind::kWrongState, path_, "CAN log not open"});
  }
  return file_->Sync();
}

std::expected<void, RecordError> CandumpLogWriter::Close() {
  if (!is_open()) {
    return std::unexpected(RecordError{RecordErrorKind::kWrongState, path_, "CAN log not open"});
  }
  auto closed = file_->Close();
  file_.reset();
  return closed;
}

bool CandumpLogWriter::is_open() const noexcept { return file_ && file_->is_open(); }

}  // namespace hrgbench::bench
