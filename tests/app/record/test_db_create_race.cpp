// Two consoles started together on a database that is not there yet: both
// create it, and both go on recording into the one file. One used to exit
// "table runs already exists" (6 of 6 tries): each read version 0, and the
// one that waited for the write lock ran the first migration again.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/record/schema.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

// A child that waits on `go`, opens `path` as a recording console does and
// begins a run; exit 0 on success, else 1 with the error on `report`.
pid_t creator(const std::string& path, int go, int report) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  char c = 0;
  if (::read(go, &c, 1) != 1) ::_exit(2);
  try {
    Recorder rec(path);
    RunInfo ri;
    ri.platform = "msd";
    ri.n = 1;
    ri.m = 1;
    rec.end_run(rec.begin_run(ri), "completed", 0, 0);
  } catch (const std::exception& e) {
    const std::string what = std::string(e.what()) + "\n";
    if (::write(report, what.data(), what.size()) < 0) ::_exit(3);
    ::_exit(1);
  }
  ::_exit(0);
}

TEST(DbCreateRace, TwoConsolesCreatingOneFileBothRecord) {
  // A few tries: the race is between two processes released at once, and
  // each try is a new file.
  for (int attempt = 0; attempt < 8; ++attempt) {
    test::TempDir dir;
    const std::string path = dir.file("new/runs.db");
    int go[2], report[2];
    ASSERT_EQ(::pipe(go), 0);
    ASSERT_EQ(::pipe(report), 0);
    const pid_t a = creator(path, go[0], report[1]), b = creator(path, go[0], report[1]);
    ASSERT_GT(a, 0);
    ASSERT_GT(b, 0);
    ::close(report[1]);
    // Both released by one write of two bytes.
    ASSERT_EQ(::write(go[1], "gg", 2), 2);
    int sa = 0, sb = 0;
    ::waitpid(a, &sa, 0);
    ::waitpid(b, &sb, 0);
    std::string errors;
    char buf[512];
    for (ssize_t n; (n = ::read(report[0], buf, sizeof buf)) > 0;) errors.append(buf, size_t(n));
    ::close(go[0]);
    ::close(go[1]);
    ::close(report[0]);
    ASSERT_TRUE(WIFEXITED(sa) && WEXITSTATUS(sa) == 0) << "try " << attempt << ": " << errors;
    ASSERT_TRUE(WIFEXITED(sb) && WEXITSTATUS(sb) == 0) << "try " << attempt << ": " << errors;
    RunStore store(path);
    EXPECT_EQ(store.list().size(), 2u) << "try " << attempt;
  }
}

}  // namespace
}  // namespace nlsoft::console
