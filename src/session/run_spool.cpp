#include "hrgbench/session/run_spool.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>
#include <utility>

namespace hrgbench::session {

namespace {

// Writes all `bytes` at `offset`; false (errno set) on failure.
bool WriteAll(int fd, const void* data, std::size_t bytes, std::int64_t offset) {
  const char* p = static_cast<const char*>(data);
  while (bytes > 0) {
    const ssize_t n = ::pwrite(fd, p, bytes, static_cast<off_t>(offset));
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (n == 0) {
      errno = ENOSPC;
      return false;
    }
    p += n;
    bytes -= static_cast<std::size_t>(n);
    offset += n;
  }
  return true;
}

// Reads all `bytes` at `offset`; false (errno set) on failure or a short file.
bool ReadAll(int fd, void* data, std::size_t bytes, std::int64_t offset) {
  char* p = static_cast<char*>(data);
  while (bytes > 0) {
    const ssize_t n = ::pread(fd, p, bytes, static_cast<off_t>(offset));
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (n == 0) {
      errno = EIO;  // the file is shorter than what was written to it
      return false;
    }
    p += n;
    bytes -= static_cast<std::size_t>(n);
    offset += n;
  }
  return true;
}

}  // namespace

std::size_t RunSampleBytes(const estimator::RunData& run) {
  return run.t_s.size() * sizeof(double) + static_cast<std::size_t>(run.y.size()) * sizeof(double);
}

RunSpool::RunSpool(std::size_t memory_budget_bytes, std::filesystem::path scratch_dir)
    : budget_(memory_budget_bytes), scratch_dir_(std::move(scratch_dir)) {}

RunSpool::~RunSpool() {
  if (fd_ >= 0) ::close(fd_);
}

std::expected<void, SessionError> RunSpool::OpenScratch() {
  std::error_code ec;
  std::filesystem::path dir = scratch_dir_;
  if (dir.empty()) dir = std::filesystem::temp_directory_path(ec);
  if (ec)
    return std::unexpected(
        SessionError{"", 0, "", "no directory for the run spool's scratch file: " + ec.message()});
  std::string name = (dir / "hrgbench-run-spool-XXXXXX").string();
  const int fd = ::mkostemp(name.data(), O_CLOEXEC);
  if (fd < 0)
    return std::unexpected(SessionError{
        dir, 0, "",
        std::string("cannot create the run spool's scratch file: ") + std::strerror(errno)});
  // Unlinked at once: the file lives as long as the descriptor, and nothing is left behind.
  ::unlink(name.c_str());
  fd_ = fd;
  return {};
}

std::expected<void, SessionError> RunSpool::Add(estimator::RunData&& run) {
  const std::size_t bytes = RunSampleBytes(run);
  Entry entry;
  entry.info = estimator::RunInfo::Of(run);
  if (spooled_runs_ == 0 && kept_bytes_ + bytes <= budget_) {
    kept_bytes_ += bytes;
    entry.kept = std::make_shared<const estimator::RunData>(std::move(run));
    runs_.push_back(std::move(entry));
    return {};
  }
  if (fd_ < 0) {
    if (auto opened = OpenScratch(); !opened) return opened;
  }
  const std::size_t t_bytes = run.t_s.size() * sizeof(double);
  if (!WriteAll(fd_, run.t_s.data(), t_bytes, end_) ||
      !WriteAll(fd_, run.y.data(), bytes - t_bytes, end_ + static_cast<std::int64_t>(t_bytes)))
    return std::unexpected(SessionError{
        scratch_dir_.empty() ? std::filesystem::temp_directory_path() : scratch_dir_, 0, "",
        "cannot write run " + std::to_string(run.id) + " to the run spool's scratch file (" +
            std::to_string(bytes) + " bytes): " + std::strerror(errno)});
  entry.offset = end_;
  end_ += static_cast<std::int64_t>(bytes);
  bytes_written_ += bytes;
  ++spooled_runs_;
  runs_.push_back(std::move(entry));
  return {};
}

estimator::RunPtr RunSpool::Load(std::size_t r) const {
  const Entry& entry = runs_[r];
  if (entry.kept) return entry.kept;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (estimator::RunPtr held = entry.in_use.lock()) return held;
  }
  // Read outside the lock: two threads loading different runs read at once. Two loading the same
  // run (rare: the passes hand each run to one thread) each read it; both copies are the same.
  std::unique_ptr<estimator::RunData> run = Buffer();
  run->id = entry.info.id;
  run->omega_rad_s = entry.info.omega_rad_s;
  run->omega_std_rad_s = entry.info.omega_std_rad_s;
  const auto n = static_cast<std::size_t>(entry.info.samples);
  run->t_s.resize(n);
  run->y.resize(4, entry.info.samples);
  const std::size_t t_bytes = n * sizeof(double);
  const std::size_t bytes = RunSampleBytes(*run);
  if (!ReadAll(fd_, run->t_s.data(), t_bytes, entry.offset) ||
      !ReadAll(fd_, run->y.data(), bytes - t_bytes,
               entry.offset + static_cast<std::int64_t>(t_bytes)))
    throw std::system_error(
        errno, std::generic_category(),
        "reading run " + std::to_string(entry.info.id) + " back from the run spool's scratch file");
  estimator::RunPtr loaded(run.release(),
                           [this](const estimator::RunData* done) { Recycle(done); });
  const std::lock_guard<std::mutex> lock(mutex_);
  entry.in_use = loaded;
  ++reads_;
  bytes_read_ += bytes;
  return loaded;
}

std::unique_ptr<estimator::RunData> RunSpool::Buffer() const {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!recycled_.empty()) {
      std::unique_ptr<estimator::RunData> buffer = std::move(recycled_.back());
      recycled_.pop_back();
      return buffer;
    }
  }
  return std::make_unique<estimator::RunData>();
}

void RunSpool::Recycle(const estimator::RunData* run) const {
  // The spool made it (Buffer) and nobody holds it any more: it is the spool's to reuse.
  std::unique_ptr<estimator::RunData> buffer(const_cast<estimator::RunData*>(run));
  const std::lock_guard<std::mutex> lock(mutex_);
  if (recycled_.size() < kRecycled) recycled_.push_back(std::move(buffer));
}

RunSpool::Counts RunSpool::counts() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  Counts c;
  c.kept_runs = runs_.size() - spooled_runs_;
  c.kept_bytes = kept_bytes_;
  c.spooled_runs = spooled_runs_;
  c.bytes_written = bytes_written_;
  c.reads = reads_;
  c.bytes_read = bytes_read_;
  return c;
}

}  // namespace hrgbench::session
