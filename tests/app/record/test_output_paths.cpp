// Where `runs export --csv` and `runs plot --svg` write, run as a user runs
// them: names for the console's own descriptors (/proc/self/fd/1, /dev/fd/1,
// /dev/stdout) get the bytes where the descriptor points (`> f.csv` fills
// f.csv, `>>` appends), a symlink is followed to its real file (the link
// stays a link), a FIFO behind a link is written in place. Every name used
// here lives in a temporary folder, except /dev/stdout, which is only ever
// given to a console whose standard output is a file of the test's, after
// the same thing went right through /proc/self/fd/1.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "app/record/recorder.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::slurp;

using test::run_process;
using test::shell_quote;

size_t lines(const std::string& s) {
  size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

bool is_symlink(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode);
}

class OutputPaths : public ::testing::Test {
 protected:
  static constexpr int kSamples = 25;
  void SetUp() override {
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "msd";
    ri.n = 1;
    ri.m = 1;
    const int64_t id = rec.begin_run(ri);
    for (int k = 0; k < kSamples; ++k) {
      Sample s;
      s.k = uint64_t(k);
      s.n = 1;
      s.m = 1;
      s.mask = protocol::telemetry_field::kYRef | protocol::telemetry_field::kYHat | protocol::telemetry_field::kU;
      s.y_ref()[0] = 0.5f;
      s.y_hat()[0] = 0.01f * float(k);
      s.u()[0] = 1;
      rec.add_sample(id, s);
    }
    rec.end_run(id, "done", kSamples, 0);
  }
  // The console as a shell runs it: `redirect` is what follows the command.
  test::ProcessResult export_to(const std::string& csv, const std::string& redirect) const {
    return run_process("sh -c " + shell_quote(std::string(NLSOFT_CONSOLE_BIN) + " runs export 1 --db " +
                                              shell_quote(db()) + " --csv " + shell_quote(csv) + " " + redirect));
  }
  std::string db() const { return dir_.file("runs.db"); }
  test::TempDir dir_;
};

TEST_F(OutputPaths, TheConsolesOwnStandardOutputGetsTheCsvWhereItPoints) {
  const std::string out = dir_.file("f.csv");
  auto r = export_to("/proc/self/fd/1", "> " + shell_quote(out));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(lines(slurp(out)), size_t(kSamples + 1)) << slurp(out);
  EXPECT_EQ(slurp(out).rfind("k,step,time_us", 0), 0u);

  // `>>` appends after what the file held.
  const std::string log = dir_.file("log.csv");
  std::ofstream(log) << "earlier line\n";
  r = export_to("/dev/fd/1", ">> " + shell_quote(log));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(slurp(log).rfind("earlier line\nk,step", 0), 0u) << slurp(log);
  EXPECT_EQ(lines(slurp(log)), size_t(kSamples + 2));

  // Only once the two above went right: /dev/stdout, into a file of ours.
  const std::string out2 = dir_.file("g.csv");
  r = export_to("/dev/stdout", "> " + shell_quote(out2));
  EXPECT_TRUE(is_symlink("/dev/stdout")) << "/dev/stdout was replaced";
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(slurp(out2), slurp(out));
  EXPECT_NE(r.output.find("25 samples written to /dev/stdout"), std::string::npos) << r.output;

  // Into a pipe: what the reader sees is the CSV.
  r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " runs export 1 --db " + shell_quote(db()) +
                  " --csv /dev/stdout 2>/dev/null | wc -l");
  EXPECT_TRUE(is_symlink("/dev/stdout"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(std::stoi(r.output), kSamples + 1) << r.output;
}

TEST_F(OutputPaths, ASymlinkStaysALinkAndItsTargetGetsTheContent) {
  const std::string data = dir_.file("data");
  ASSERT_EQ(::mkdir(data.c_str(), 0755), 0);
  const std::string real = data + "/real.csv";
  std::ofstream(real) << "old content\n";
  ASSERT_EQ(::chmod(real.c_str(), 0640), 0);
  // A relative link, and a link to that link.
  const std::string link = dir_.file("latest.csv"), link2 = dir_.file("again.csv");
  ASSERT_EQ(::symlink("data/real.csv", link.c_str()), 0);
  ASSERT_EQ(::symlink(link.c_str(), link2.c_str()), 0);

  auto r = export_to(link2, "");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(is_symlink(link)) << "the link was replaced by a file";
  EXPECT_TRUE(is_symlink(link2)) << "the link was replaced by a file";
  EXPECT_EQ(lines(slurp(real)), size_t(kSamples + 1)) << slurp(real);
  struct stat st {};
  ASSERT_EQ(::stat(real.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u) << "the replaced file keeps its mode";

  // A dangling link: the file it names is created, the link stays.
  const std::string dangling = dir_.file("new.csv");
  ASSERT_EQ(::symlink("data/created.csv", dangling.c_str()), 0);
  r = export_to(dangling, "");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(is_symlink(dangling));
  EXPECT_EQ(lines(slurp(data + "/created.csv")), size_t(kSamples + 1));

  // A link to a folder is refused, naming the path.
  const std::string to_dir = dir_.file("dirlink");
  ASSERT_EQ(::symlink("data", to_dir.c_str()), 0);
  r = export_to(to_dir, "");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("cannot write " + to_dir + ": it is a directory"), std::string::npos) << r.output;
  EXPECT_TRUE(is_symlink(to_dir));
}

TEST_F(OutputPaths, AFifoBehindALinkIsWrittenInPlace) {
  const std::string fifo = dir_.file("pipe"), link = dir_.file("to-pipe"), got = dir_.file("got.csv");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ASSERT_EQ(::symlink(fifo.c_str(), link.c_str()), 0);
  const auto r = run_process("cat " + shell_quote(fifo) + " > " + shell_quote(got) + " & " +
                             std::string(NLSOFT_CONSOLE_BIN) + " runs export 1 --db " + shell_quote(db()) + " --csv " +
                             shell_quote(link) + "; s=$?; wait; exit $s");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(is_symlink(link));
  struct stat st {};
  ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_EQ(lines(slurp(got)), size_t(kSamples + 1));
}

TEST_F(OutputPaths, APlotToStandardOutputFillsTheRedirectedFile) {
  if (run_process("command -v gnuplot").code != 0) GTEST_SKIP() << "gnuplot is not installed";
  const std::string out = dir_.file("p.svg");
  const std::string cmd = std::string(NLSOFT_CONSOLE_BIN) + " runs plot 1 --db " + shell_quote(db());
  auto r = run_process("sh -c " + shell_quote(cmd + " --svg /proc/self/fd/1 > " + shell_quote(out)));
  ASSERT_EQ(r.code, 0) << r.output;
  ASSERT_NE(slurp(out).find("</svg>"), std::string::npos);
  const std::string out2 = dir_.file("q.svg");
  r = run_process("sh -c " + shell_quote(cmd + " --svg /dev/stdout > " + shell_quote(out2)));
  EXPECT_TRUE(is_symlink("/dev/stdout")) << "/dev/stdout was replaced";
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(slurp(out2).find("</svg>"), std::string::npos);
}

}  // namespace
}  // namespace nlsoft::console
