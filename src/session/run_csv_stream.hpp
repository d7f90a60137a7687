#pragma once
// Internal: one run's CSV, streamed to <run>.csv.partial while the run goes on and made final by an
// fsync'ed rename, so a run of any length never has to sit in memory and its data reaches the disk
// during the run. The text is exactly what session::WriteRunCsv writes for the same samples
// (header t_s,y1,y2,y3,y4 then the extra columns in name order, shortest round-trip numbers).

#include <cstdint>
#include <expected>
#include <filesystem>
#include <memory>
#include <span>

#include "append_file.hpp"
#include "hrgbench/session/session_record_types.hpp"

namespace hrgbench::bench::internal {

class RunCsvStream {
 public:
  // Creates `partial_path` (refuses an existing file) and buffers the header.
  static std::expected<RunCsvStream, RecordError> Open(const std::filesystem::path& partial_path,
                                                       bool with_measured_omega,
                                                       bool with_temperature,
                                                       bool with_resonant_frequency,
                                                       std::int64_t flush_interval_ns);

  // Validates the whole batch (finite values, t_s strictly increasing), then formats and buffers
  // it; writes out per AppendFile's policy. A refused batch writes nothing.
  std::expected<void, RecordError> Append(std::span<const GyroSampleRecord> samples);

  // Writes out, fsyncs, closes and renames the partial file to `final_path` (fsyncing the
  // directory). On failure the partial file is left as it is and the stream is closed.
  std::expected<void, RecordError> Finish(const std::filesystem::path& final_path);

  // Writes out what is buffered (errors dropped) and closes; the partial file stays.
  void Close() noexcept;

  std::uint64_t samples() const noexcept { return samples_; }
  const std::filesystem::path& partial_path() const noexcept { return file_->path(); }

 private:
  std::unique_ptr<AppendFile> file_;
  bool with_measured_omega_ = false;
  bool with_temperature_ = false;
  bool with_resonant_frequency_ = false;
  std::uint64_t samples_ = 0;
  double last_t_s_ = 0.0;
};

}  // namespace hrgbench::bench::internal
