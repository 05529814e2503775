// `runs plot`: pictures of recorded runs drawn by gnuplot, headless. Two
// short runs on the simulated HASEL rig, then SVG and PNG files checked for
// what they must show. Skipped, saying why, without gnuplot.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;
using nlsoft::test::slurp;

using test::run_process;
using test::shell_quote;

bool have_gnuplot() { return run_process("command -v gnuplot").code == 0; }

class RunsPlot : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
  test::ProcessResult console(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
  }
  // Two runs of the Swirl with different Lambda: what a tuning session leaves.
  void record_two_runs() {
    const std::string script = dir_.file("two.nls");
    std::ofstream(script) << "ref swirl\nrun 1s label=lambda1\nset Lambda 4\nrun 1s label=lambda4\n";
    const auto r = console("--sim hasel --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(script));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  std::string db() const { return dir_.file("runs.db"); }
  test::TempDir dir_;
};

TEST_F(RunsPlot, SvgOfOneRunShowsEverySeriesAndTheParameters) {
  if (!have_gnuplot()) GTEST_SKIP() << "gnuplot is not installed: runs plot needs it (apt-get install gnuplot-nox)";
  record_two_runs();
  const std::string svg = dir_.file("run1.svg");
  const auto r = console("runs plot 1 --svg " + shell_quote(svg) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "run 1 drawn to ")) << r.output;
  const std::string s = slurp(svg);
  ASSERT_TRUE(contains(s, "<svg")) << s.substr(0, 400);
  for (const char* title : {"output y0", "output y1", "output y2", ">y_ref<", ">y_hat<", ">y_true<", ">u0 h1<", ">u5 h6<",
                            "actuator inputs u", "x-y path", ">y_true path<"})
    EXPECT_TRUE(contains(s, title)) << title;
  // The axes carry the rig's names and units (rigs/hasel.toml: x, y, z in mm).
  for (const char* axis : {"output y0: x (mm)", "output y2: z (mm)", ">x (mm)<", ">y (mm)<"})
    EXPECT_TRUE(contains(s, axis)) << axis;
  // The caption: which run, and its parameters at start.
  EXPECT_TRUE(contains(s, "run 1 (lambda1): hasel")) << s.substr(0, 2000);
  EXPECT_TRUE(contains(s, "Lambda=1 1 1 1 1 1")) << s.substr(0, 2000);
}

TEST_F(RunsPlot, TwoRunsOverlayAndPngWorksToo) {
  if (!have_gnuplot()) GTEST_SKIP() << "gnuplot is not installed: runs plot needs it (apt-get install gnuplot-nox)";
  record_two_runs();
  const std::string svg = dir_.file("both.svg"), png = dir_.file("both.png");
  auto r = console("runs plot 1 2 --svg " + shell_quote(svg) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string s = slurp(svg);
  EXPECT_TRUE(contains(s, ">run 1 y_true<")) << s.substr(0, 400);
  EXPECT_TRUE(contains(s, ">run 2 y_true<"));
  EXPECT_TRUE(contains(s, ">run 2 u5 h6<"));
  EXPECT_TRUE(contains(s, "Lambda=4 4 4 4 4 4")) << "the second run's parameters are in the caption";
  // runs compare draws them too, beside its table.
  const std::string cmp = dir_.file("compare.svg");
  r = console("runs compare 1 2 --svg " + shell_quote(cmp) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "parameters that differ")) << r.output;
  EXPECT_TRUE(contains(slurp(cmp), ">run 2 y_true<"));
  r = console("runs plot 1 2 --png " + shell_quote(png) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(slurp(png).substr(0, 4), "\x89PNG");
}

// An identification run ran no controller and tracked no reference: its
// caption has neither a tracking figure nor the controller's parameters,
// and its picture has what it recorded, the sensors l among them.
TEST_F(RunsPlot, AnIdentificationRunShowsItsExcitationAndSensorsNotTracking) {
  if (!have_gnuplot()) GTEST_SKIP() << "gnuplot is not installed: runs plot needs it (apt-get install gnuplot-nox)";
  auto r = console("ident --sim hasel --signal prbs --duration 3s --sim-fast --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string svg = dir_.file("ident.svg");
  r = console("runs plot 1 --svg " + shell_quote(svg) + " --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string s = slurp(svg);
  ASSERT_TRUE(contains(s, "<svg")) << s.substr(0, 400);
  EXPECT_TRUE(contains(s, "identification on hasel")) << s.substr(0, 2000);
  EXPECT_TRUE(contains(s, "excitation")) << s.substr(0, 2000);
  EXPECT_FALSE(contains(s, "nrmse")) << s.substr(0, 2000);
  EXPECT_FALSE(contains(s, "Lambda=")) << s.substr(0, 2000);
  for (const char* what : {"sensors l", ">l0 b1x (gauss)<", ">l17 b6z (gauss)<", ">l (gauss)<", "actuator inputs u"})
    EXPECT_TRUE(contains(s, what)) << what;
}

// runs compare: a parameter with several elements gets one line per run,
// element under element, not both vectors run together on one line.
TEST_F(RunsPlot, CompareShowsVectorsOneRunPerLineAligned) {
  record_two_runs();
  const auto r = console("runs compare 1 2 --db " + shell_quote(db()));
  ASSERT_EQ(r.code, 0) << r.output;
  std::vector<std::string> lines;
  std::istringstream in(r.output);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  size_t at = lines.size();
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i] == "  Lambda") at = i;
  ASSERT_LT(at + 2, lines.size()) << r.output;
  const std::string a = lines[at + 1], b = lines[at + 2];
  EXPECT_EQ(a.rfind("    run 1 ", 0), 0u) << r.output;
  EXPECT_EQ(b.rfind("    run 2 ", 0), 0u) << r.output;
  EXPECT_EQ(a.find('4'), std::string::npos) << "run 2's values on run 1's line: " << a;
  // Element k of one run sits above element k of the other.
  ASSERT_EQ(a.size(), b.size()) << a << "\n" << b;
  for (size_t i = 10; i < a.size(); ++i)
    EXPECT_EQ(a[i] == ' ', b[i] == ' ') << "column " << i << ":\n" << a << "\n" << b;
  EXPECT_NE(a.find("1  1  1  1  1  1"), std::string::npos) << a;
  EXPECT_NE(b.find("4  4  4  4  4  4"), std::string::npos) << b;
}

TEST_F(RunsPlot, BadRequestsSayWhatIsWrongAndWriteNothing) {
  if (!have_gnuplot()) GTEST_SKIP() << "gnuplot is not installed: runs plot needs it (apt-get install gnuplot-nox)";
  record_two_runs();
  const std::string out = dir_.file("x.svg");
  auto r = console("runs plot 1 --db " + shell_quote(db()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "give one of --svg FILE or --png FILE")) << r.output;
  r = console("runs plot 9 --svg " + shell_quote(out) + " --db " + shell_quote(db()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "no run 9")) << r.output;
  // A gnuplot that is not there: the message says what to install.
  r = run_process("NLSOFT_GNUPLOT=/nonexistent/gnuplot " + std::string(NLSOFT_CONSOLE_BIN) + " runs plot 1 --svg " +
                  shell_quote(out) + " --db " + shell_quote(db()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "apt-get install gnuplot-nox")) << r.output;
  EXPECT_FALSE(std::ifstream(out).good()) << "nothing written on a failure";
}

}  // namespace
}  // namespace nlsoft::console
