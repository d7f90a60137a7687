#include "run_csv_stream.hpp"

#include <charconv>
#include <cmath>
#include <string>

#include "hrgbench/session/number_text.hpp"

namespace hrgbench::bench::internal {
namespace {

namespace fs = std::filesystem;

// Numbers as session::WriteRunCsv writes them (one function: the two must stay bit-identical).
using session::AppendNumber;

void AppendNumber(std::string& out, std::uint32_t value) {
  char buffer[16];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

std::string Show(double value) { return session::NumberText(value); }

}  // namespace

std::expected<RunCsvStream, RecordError> RunCsvStream::Open(const fs::path& partial_path,
                                                            bool with_measured_omega,
                                                            bool with_temperature,
                                                            bool with_resonant_frequency,
                                                            std::int64_t flush_interval_ns) {
  auto file = AppendFile::Open(partial_path, AppendFile::Mode::kCreateNew, flush_interval_ns);
  if (!file) return std::unexpected(file.error());
  RunCsvStream stream;
  stream.file_ = std::move(*file);
  stream.with_measured_omega_ = with_measured_omega;
  stream.with_temperature_ = with_temperature;
  stream.with_resonant_frequency_ = with_resonant_frequency;
  std::string& out = stream.file_->buffer();
  out += "t_s,y1,y2,y3,y4";
  // Extra columns in name order, as WriteRunCsv (a std::map) orders them.
  if (with_resonant_frequency) out += ",freq_hz";
  if (with_measured_omega) out += ",omega_meas_rad_s";
  out += ",seq";
  if (with_temperature) out += ",temp_c";
  out += '\n';
  return stream;
}

std::expected<void, RecordError> RunCsvStream::Append(std::span<const GyroSampleRecord> samples) {
  if (!file_ || !file_->is_open()) {
    return std::unexpected(RecordError{RecordErrorKind::kWrongState, {}, "run file closed"});
  }
  auto refuse = [this](std::uint64_t index, std::string message) {
    return std::unexpected(
        RecordError{RecordErrorKind::kInvalidArgument, file_->path(),
                    "sample " + std::to_string(samples_ + index) + ": " + std::move(message)});
  };
  double previous_t_s = last_t_s_;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const GyroSampleRecord& s = samples[k];
    if (!std::isfinite(s.t_s)) return refuse(k, "non-finite t_s " + Show(s.t_s));
    if ((samples_ > 0 || k > 0) && !(s.t_s > previous_t_s)) {
      return refuse(k,
                    "t_s not strictly increasing: " + Show(s.t_s) + " after " + Show(previous_t_s));
    }
    previous_t_s = s.t_s;
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(s.y[c])) {
        return refuse(k, "non-finite y" + std::to_string(c + 1) + " " + Show(s.y[c]));
      }
    }
    if (with_resonant_frequency_ && !std::isfinite(s.resonant_frequency_hz)) {
      return refuse(k, "non-finite freq_hz " + Show(s.resonant_frequency_hz));
    }
    if (with_measured_omega_ && !std::isfinite(s.measured_omega_rad_s)) {
      return refuse(k, "non-finite omega_meas_rad_s " + Show(s.measured_omega_rad_s));
    }
    if (with_temperature_ && !std::isfinite(s.temperature_c)) {
      return refuse(k, "non-finite temp_c " + Show(s.temperature_c));
    }
  }

  std::string& out = file_->buffer();
  for (const GyroSampleRecord& s : samples) {
    AppendNumber(out, s.t_s);
    for (int c = 0; c < 4; ++c) {
      out += ',';
      AppendNumber(out, s.y[c]);
    }
    if (with_resonant_frequency_) {
      out += ',';
      AppendNumber(out, s.resonant_frequency_hz);
    }
    if (with_measured_omega_) {
      out += ',';
      AppendNumber(out, s.measured_omega_rad_s);
    }
    out += ',';
    AppendNumber(out, s.seq);
    if (with_temperature_) {
      out += ',';
      AppendNumber(out, s.temperature_c);
    }
    out += '\n';
    // Bound the buffer within a large batch too.
    if (out.size() >= AppendFile::kFlushBytes) {
      if (auto flushed = file_->Flush(); !flushed) return flushed;
    }
  }
  if (!samples.empty()) {
    samples_ += samples.size();
    last_t_s_ = samples.back().t_s;
  }
  return file_->MaybeFlush();
}

std::expected<void, RecordError> RunCsvStream::Finish(const fs::path& final_path) {
  if (!file_ || !file_->is_open()) {
    return std::unexpected(
        RecordError{RecordErrorKind::kWrongState, final_path, "run file closed"});
  }
  const fs::path partial = file_->path();
  if (auto closed = file_->Close(); !closed) {
    file_->Abandon();
    return closed;
  }
  return RenameDurably(partial, final_path);
}

void RunCsvStream::Close() noexcept {
  if (!file_ || !file_->is_open()) return;
  (void)file_->Flush();
  file_->Abandon();
}

}  // namespace hrgbench::bench::internal
