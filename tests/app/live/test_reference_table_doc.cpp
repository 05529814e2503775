// The reference table CONSOLE.md documents ("Reference tables: `ref load`"),
// taken from the document itself with its script, run against the
// simulator: the firmware follows it point by point, each held as long as
// the script says, and a row of the wrong width is refused at its line.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "app/record/run_store.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

using test::run_process;
using test::shell_quote;

// The fenced block of CONSOLE.md whose first line is "# file: NAME".
std::string documented_file(const std::string& name) {
  std::ifstream in(std::string(NLSOFT_SOURCE_MODELS_DIR) + "/../CONSOLE.md");
  std::string line, block;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      if (inside && block.rfind("# file: " + name + "\n", 0) == 0) return block;
      inside = !inside;
      block.clear();
      continue;
    }
    if (inside) block += line + "\n";
  }
  return "";
}

TEST(ReferenceTable, TheDocumentedTableIsFollowedPointByPoint) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  const std::string csv = documented_file("square.csv"), script = documented_file("square.nls");
  ASSERT_FALSE(csv.empty()) << "CONSOLE.md shows no square.csv";
  ASSERT_NE(script.find("ref load square.csv hold=130"), std::string::npos) << script;
  std::ofstream(dir.file("square.csv")) << csv;
  std::ofstream(dir.file("square.nls")) << script;
  const std::string db = dir.file("runs.db");
  const auto r = run_process("cd " + shell_quote(dir.path) + " && " + NLSOFT_CONSOLE_BIN +
                             " --script square.nls --sim hasel --sim-fast --db " + shell_quote(db) + " 2>&1");
  ASSERT_EQ(r.code, 0) << r.output;

  // Every point of the table, in its order, each held 130 steps (a second).
  RunStore store(db);
  const RunSeries s = store.series(1);
  ASSERT_TRUE(s.has_y_ref);
  ASSERT_EQ(s.n, 3);
  std::vector<std::pair<float, float>> corners;
  size_t held = 0, longest = 0;
  for (size_t i = 0; i < s.rows(); ++i) {
    const std::pair<float, float> xy{s.y_ref[3 * i], s.y_ref[3 * i + 1]};
    EXPECT_FLOAT_EQ(s.y_ref[3 * i + 2], 8.0f) << "row " << i;
    if (corners.empty() || corners.back() != xy) corners.push_back(xy), held = 0;
    longest = std::max(longest, ++held);
  }
  const std::vector<std::pair<float, float>> want = {{-5, -5}, {5, -5}, {5, 5}, {-5, 5}, {-5, -5}};
  ASSERT_GE(corners.size(), 4u);
  for (size_t i = 0; i < corners.size() && i < want.size(); ++i) EXPECT_EQ(corners[i], want[i]) << "point " << i;
  EXPECT_GE(longest, 130u);
}

TEST(ReferenceTable, ARowOfTheWrongWidthIsRefusedAtItsLine) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  std::ofstream(dir.file("bad.csv")) << "x,y,z\n-5,-5,8\n5,-5\n";
  std::ofstream(dir.file("bad.nls")) << "ref load " << dir.file("bad.csv") << "\nrun 1s\n";
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --script " + shell_quote(dir.file("bad.nls")) +
                             " --sim hasel --sim-fast --no-record 2>&1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(dir.file("bad.csv") + ":3: 2 values on this row, the firmware wants 3 per point"),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace nlsoft::console
