// Browsing a recording the user may not write: another user's database in
// a folder they cannot write, or a read-only file in a folder they can.
// `runs list/show/export/compare` work, and no -shm/-wal file is left
// beside the database. The suite runs as root; each command runs in a
// child that has dropped to nobody before exec, as that user would run it.
#include <gtest/gtest.h>
#include <grp.h>
#include <pwd.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <filesystem>

#include "app/record/recorder.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

using test::shell_quote;

// `command` through /bin/sh as nobody; output and exit code.
test::ProcessResult run_as_nobody(const std::string& command) {
  test::ProcessResult r;
  const passwd* nobody = ::getpwnam("nobody");
  if (!nobody) return r;
  int fds[2];
  if (::pipe(fds) != 0) return r;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[1], 1);
    ::dup2(fds[1], 2);
    ::close(fds[0]);
    if (::setgroups(0, nullptr) != 0 || ::setgid(nobody->pw_gid) != 0 || ::setuid(nobody->pw_uid) != 0) ::_exit(99);
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(fds[1]);
  std::array<char, 4096> buf;
  ssize_t n;
  while ((n = ::read(fds[0], buf.data(), buf.size())) > 0) r.output.append(buf.data(), size_t(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

class ReadOnlyDb : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::geteuid() != 0) GTEST_SKIP() << "needs root, to browse as another user";
    ASSERT_EQ(::chmod(dir_.path.c_str(), 0755), 0);  // nobody may enter
    folder_ = dir_.file("ro");
    ASSERT_EQ(::mkdir(folder_.c_str(), 0755), 0);
    db_ = folder_ + "/ro.db";
    Recorder rec(db_);
    for (int i = 0; i < 2; ++i) {
      RunInfo ri;
      ri.platform = "msd";
      ri.n = 1;
      ri.m = 1;
      const int64_t id = rec.begin_run(ri);
      for (uint64_t k = 0; k < 20; ++k) {
        Sample s;
        s.k = k;
        s.n = 1;
        s.m = 1;
        s.mask = protocol::telemetry_field::kYRef | protocol::telemetry_field::kYHat;
        rec.add_sample(id, s);
      }
      rec.end_run(id, "completed", 20, 0);
    }
  }
  void browse_and_check() {
    ASSERT_EQ(::chmod(db_.c_str(), 0444), 0);
    const std::string bin = std::string(NLSOFT_CONSOLE_BIN) + " runs ";
    const std::string db = " --db " + shell_quote(db_);
    for (const std::string cmd : {"list", "show 1", "compare 1 2", "export 2"}) {
      const auto r = run_as_nobody(bin + cmd + db);
      EXPECT_EQ(r.code, 0) << cmd << ": " << r.output;
      EXPECT_FALSE(contains(r.output, "readonly")) << cmd << ": " << r.output;
    }
    EXPECT_TRUE(contains(run_as_nobody(bin + "export 2" + db).output, "run 2: 20 samples written"));
    EXPECT_FALSE(std::filesystem::exists(db_ + "-shm")) << "a -shm file was created";
    EXPECT_FALSE(std::filesystem::exists(db_ + "-wal")) << "a -wal file was created";
  }
  test::TempDir dir_;
  std::string folder_, db_;
};

TEST_F(ReadOnlyDb, AnotherUsersDatabaseInAFolderTheyCannotWriteIsBrowsed) {
  browse_and_check();
}

TEST_F(ReadOnlyDb, AReadOnlyFileInAWritableFolderGetsNoShmOrWalFiles) {
  ASSERT_EQ(::chmod(folder_.c_str(), 0777), 0);
  browse_and_check();
}

}  // namespace
}  // namespace nlsoft::console
