// A full disk or an unwritable directory: the recorder returns kIo (never throws, never crashes),
// and the runs already final stay intact and readable.
//   - tiny tmpfs (mount(2), needs root / CAP_SYS_ADMIN; skipped with a message otherwise): ENOSPC
//   - RLIMIT_FSIZE in a forked child (works for anyone): EFBIG, the same path through the code
//   - read-only tmpfs (root) or chmod 0500 (non-root; root bypasses permissions)

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "record_test_dir.hpp"
#include "recorder_fixture.hpp"
#include "required_tool.hpp"

namespace hrgbench::bench {
namespace {

namespace fs = std::filesystem;
using record_test::ExpectCompleteRuns;
using record_test::RecordRun;
using record_test::StartFor;

// Mounts a tmpfs of `size` at `dir` for the scope (lazy unmount at the end).
class TmpfsMount {
 public:
  TmpfsMount(const fs::path& dir, const std::string& options, unsigned long flags = 0) : dir_(dir) {
    if (::mount("tmpfs", dir.c_str(), "tmpfs", flags, options.c_str()) == 0) {
      mounted_ = true;
    } else {
      error_ = std::strerror(errno);
    }
  }
  ~TmpfsMount() {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  bool mounted() const { return mounted_; }
  const std::string& error() const { return error_; }

 private:
  fs::path dir_;
  bool mounted_ = false;
  std::string error_;
};

TEST(RecorderDiskFull, TinyTmpfsFillsMidRunAndRunsOneAndTwoStayIntact) {
  testing::ScratchDir scratch("record_tmpfs");
  // 512 KiB: session.json, runs 1 and 2 (~45 KiB each) fit; run 3's 20 000 samples do not.
  TmpfsMount mount(scratch.path(), "size=512k,mode=0755");
  HRGBENCH_REQUIRE(mount.mounted(), "cannot mount a tmpfs here (" << mount.error() << ")");
  const fs::path dir = scratch / "session";
  const SessionHeader header = testing::SyntheticHeader(3);
  RecorderOptions options;
  options.flush_interval_ns = 0;
  auto recorder = SessionRecorder::Create(dir, header, options);
  ASSERT_TRUE(recorder.has_value()) << recorder.error().ToString();
  ASSERT_TRUE(RecordRun(*recorder, header.runs[0]).has_value());
  ASSERT_TRUE(RecordRun(*recorder, header.runs[1]).has_value());

  auto failed = RecordRun(*recorder, header.runs[2], 20'000);
  ASSERT_FALSE(failed.has_value()) << "a 512 KiB tmpfs took 20 000 samples";
  EXPECT_EQ(failed.error().kind, RecordErrorKind::kIo);
  EXPECT_NE(failed.error().message.find(std::strerror(ENOSPC)), std::string::npos)
      << failed.error().ToString();
  EXPECT_FALSE(recorder->open_run_id().has_value());  // the failure closed the run
  ExpectCompleteRuns(dir, header, {1, 2});

  // Closing may itself fail on the full disk; either way the record is not a success.
  auto closed = recorder->Close({OutcomeKind::kError, failed.error().ToString(), {}, {}, {}});
  auto read = session::ReadSession(dir);
  ASSERT_TRUE(read.has_value()) << read.error().ToString();
  if (closed) {
    EXPECT_EQ(read->document["outcome"]["kind"], "ERROR");
    EXPECT_EQ(read->document["runs"][2]["status"], "aborted");
  } else {
    EXPECT_EQ(closed.error().kind, RecordErrorKind::kIo);
    EXPECT_EQ(read->document["state"], "running");
  }
  ExpectCompleteRuns(dir, header, {1, 2});
  // No temporary of a failed session.json write is left behind.
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos);
  }
}

// In a child (the limit must not touch the test runner's own files): every file is limited to
// 200 KB, so run 3's 20 000 samples hit EFBIG mid-run while session.json still fits.
TEST(RecorderDiskFull, FileSizeLimitMidRunIsAnErrorAndTheSessionClosesAsError) {
  testing::ScratchDir scratch("record_fsize");
  const fs::path dir = scratch / "session";
  const SessionHeader header = testing::SyntheticHeader(3);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::signal(SIGXFSZ, SIG_IGN);  // write(2) then fails with EFBIG instead of killing us
    const rlimit limit{200'000, 200'000};
    if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(10);
    RecorderOptions options;
    options.flush_interval_ns = 0;
    auto recorder = SessionRecorder::Create(dir, header, options);
    if (!recorder) ::_exit(11);
    if (!RecordRun(*recorder, header.runs[0]) || !RecordRun(*recorder, header.runs[1])) ::_exit(12);
    auto failed = RecordRun(*recorder, header.runs[2], 20'000);
    if (failed) ::_exit(13);
    if (failed.error().kind != RecordErrorKind::kIo) ::_exit(14);
    if (!recorder->Close({OutcomeKind::kError, failed.error().ToString(), {}, {}, {}})) ::_exit(15);
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "child died of signal " << WTERMSIG(status);
  ASSERT_EQ(WEXITSTATUS(status), 0) << "step that failed: see the exit codes in the child";
  ExpectCompleteRuns(dir, header, {1, 2});
  auto read = session::ReadSession(dir);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->document["outcome"]["kind"], "ERROR");
  EXPECT_EQ(read->document["outcome"]["exit_code"], 2);
  EXPECT_NE(read->document["outcome"]["reason"].get<std::string>().find(std::strerror(EFBIG)),
            std::string::npos);
  EXPECT_EQ(read->document["runs"][2]["status"], "aborted");
  EXPECT_NE(read->document["runs"][2]["end"]["reason"].get<std::string>().find("recorder:"),
            std::string::npos);
}

TEST(RecorderDiskFull, UnwritableDirectoryIsAnErrorNotAThrow) {
  testing::ScratchDir scratch("record_readonly");
  std::optional<TmpfsMount> mount;
  if (::geteuid() == 0) {
    mount.emplace(scratch.path(), "size=64k", MS_RDONLY);
    HRGBENCH_REQUIRE(mount->mounted(),
                     "root bypasses chmod and a read-only tmpfs cannot be "
                     "mounted ("
                         << mount->error() << ")");
  } else {
    fs::permissions(scratch.path(), fs::perms::owner_read | fs::perms::owner_exec);
  }
  auto created = SessionRecorder::Create(scratch / "session", testing::SyntheticHeader(1));
  if (::geteuid() != 0) fs::permissions(scratch.path(), fs::perms::owner_all);
  ASSERT_FALSE(created.has_value());
  EXPECT_EQ(created.error().kind, RecordErrorKind::kIo);
  EXPECT_FALSE(created.error().message.empty());
}

}  // namespace
}  // namespace hrgbench::bench
