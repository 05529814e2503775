// app/'s folders stand in one order, and every #include "app/..." runs from
// a higher one down to a lower one (or stays in its folder): never up. An
// include that climbs (live/ reaching into tui/, tune/ into script/ for a
// helper) is the knot issue 58 untied; this test fails when one comes back.
// It reads the sources, so it needs nothing built but itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The order, highest first, as the code stands: each folder includes only
// folders after it. Derived from the includes themselves (who includes whom):
//   tui         -> script, tune, live, link, record
//   script      -> tune, live, link, record, model, text
//   tune        -> live, link, record, text
//   replay      -> live, link, record, simulate
//   live        -> link, record, firmware, model, text
//   conformance -> link, firmware
//   link        -> simulate
//   record      -> simulate, metrics, model, text
//   simulate    -> metrics, model
//   firmware    -> model
//   rig         -> model
// That graph has no cycle; where two folders include neither way (link and
// record, rig and firmware) the line below picks one order. Moving a folder
// up or down here is a decision about the design, not a fix for this test.
const std::vector<std::string> kOrder = {
    "(entry)",  // kEntries: the programs and the console's entry, above all
    "tui",          // the ncurses console: plots, panels, the ':' line
    "script",       // the script language: parser, checks, runner
    "tune",         // the tuner (NLopt) and its command
    "replay",       // a recorded run again, in this process, with changes
    "live",         // the live console: connect, runs, ident, references
    "conformance",  // the firmware conformance suite
    "target",       // what a command talks to: PORT, --sim, --qemu and its image
    "link",         // serial link, session, device
    "record",       // recorded runs (SQLite), runs ..., exports
    "simulate",     // the offline closed loop
    "firmware",     // Cortex-M images from rig files
    "rig",          // rig commands over host/rig
    "metrics",      // tracking metrics
    "model",        // the model pipeline: dataset, train, import
    "text",         // durations and a line's words as typed
    "(helpers)",    // the other files at app/'s root: progress bar, gnuplot text, ...
};

// Files that sit above every folder: main() and the console's entry beside
// it, which start the live console and then the TUI or a script, and the
// fuzz targets, programs of their own that drive the intake across rooms
// (a prefix ending in '/' names a folder of them).
const std::vector<std::string> kEntries = {
    "main.cpp", "console_command.hpp", "console_command.cpp", "link/fuzz/", "record/fuzz/",
};

// Folders under app/ that hold no code: shipped models, packaging.
const std::vector<std::string> kNoCode = {"models", "dist"};

// The layer of a path under app/ ("live/ident_plan.cpp"): its index in
// kOrder, or -1 for a folder the order does not name.
int layer_of(const std::string& path) {
  for (const std::string& e : kEntries)
    if (e.back() == '/' ? path.rfind(e, 0) == 0 : path == e) return 0;
  const size_t slash = path.find('/');
  const std::string layer = slash == std::string::npos ? "(helpers)" : path.substr(0, slash);
  const auto it = std::find(kOrder.begin(), kOrder.end(), layer);
  return it == kOrder.end() ? -1 : int(it - kOrder.begin());
}

std::string folder_of(const std::string& path) {
  const int l = layer_of(path);
  return l < 0 ? path.substr(0, path.find('/')) : kOrder[size_t(l)];
}

// What is wrong with `from` (a path under app/) including "app/<included>":
// empty when nothing is.
std::string climb(const std::string& from, const std::string& included) {
  const int a = layer_of(from), b = layer_of(included);
  if (a < 0) return "'" + folder_of(from) + "/' is not in kOrder (tests/app/test_app_layers.cpp): place it";
  if (b < 0) return "'" + folder_of(included) + "/' is not in kOrder (tests/app/test_app_layers.cpp): place it";
  if (b < a) return "climbs from " + folder_of(from) + " up to " + folder_of(included);
  return "";
}

struct Include {
  std::string file;  // under app/
  int line;
  std::string target;  // what follows "app/"
};

std::vector<Include> app_includes(const fs::path& app) {
  static const std::regex kInclude(R"(^\s*#\s*include\s*"app/([^"]+)\")");
  std::vector<Include> out;
  for (const auto& entry : fs::recursive_directory_iterator(app)) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
    std::ifstream in(entry.path());
    std::string text;
    int n = 0;
    std::smatch m;
    while (std::getline(in, text)) {
      ++n;
      if (std::regex_search(text, m, kInclude))
        out.push_back({fs::relative(entry.path(), app).generic_string(), n, m[1].str()});
    }
  }
  return out;
}

const fs::path kApp = fs::path(NLSOFT_SOURCE_DIR) / "app";

TEST(AppLayers, IncludesRunDownward) {
  const std::vector<Include> includes = app_includes(kApp);
  // A scan that found nothing would pass anything.
  ASSERT_GT(includes.size(), 300u) << "too few #include \"app/...\" lines under " << kApp;
  size_t across = 0;
  for (const Include& i : includes) {
    const std::string wrong = climb(i.file, i.target);
    EXPECT_EQ(wrong, "") << "app/" << i.file << ":" << i.line << ": #include \"app/" << i.target << "\"";
    across += folder_of(i.file) != folder_of(i.target);
  }
  EXPECT_GT(across, 100u) << "the scan should see includes between folders";
}

// Every folder of app/ that holds code is in the order, and every folder the
// order names is there: a new folder is placed on purpose, a removed one
// leaves the list.
TEST(AppLayers, TheOrderNamesEveryFolder) {
  std::vector<std::string> folders;
  for (const auto& entry : fs::directory_iterator(kApp))
    if (entry.is_directory()) folders.push_back(entry.path().filename().string());
  for (const std::string& f : folders) {
    if (std::find(kNoCode.begin(), kNoCode.end(), f) != kNoCode.end()) continue;
    EXPECT_NE(std::find(kOrder.begin(), kOrder.end(), f), kOrder.end())
        << "app/" << f << "/ is not in kOrder: place it where its includes say";
  }
  for (const std::string& f : kOrder) {
    if (f.front() != '(') {
      EXPECT_NE(std::find(folders.begin(), folders.end(), f), folders.end()) << "kOrder names app/" << f << "/";
    }
  }
  for (const std::string& e : kEntries) EXPECT_TRUE(fs::exists(kApp / e)) << "app/" << e;
}

// The check itself: the includes issue 58 removed would fail it, the ones
// that stay would not.
TEST(AppLayers, AClimbIsCaught) {
  EXPECT_EQ(climb("live/console_command.cpp", "tui/tui_app.hpp"), "climbs from live up to tui");
  EXPECT_EQ(climb("tune/tuner.cpp", "script/script_parser.hpp"), "climbs from tune up to script");
  EXPECT_EQ(climb("record/runs_command.cpp", "script/script_parser.hpp"), "climbs from record up to script");
  EXPECT_EQ(climb("progress_bar.hpp", "live/live_console.hpp"), "climbs from (helpers) up to live");
  EXPECT_EQ(climb("text/duration.cpp", "progress_bar.hpp"), "");
  EXPECT_EQ(climb("console_command.cpp", "tui/tui_app.hpp"), "");
  EXPECT_EQ(climb("main.cpp", "console_command.hpp"), "");
  EXPECT_EQ(climb("link/fuzz/fuzz_intake.cpp", "live/sample_intake.hpp"), "");
  EXPECT_EQ(climb("script/script_parser.cpp", "text/tokenize.hpp"), "");
  EXPECT_EQ(climb("live/x.cpp", "live/y.hpp"), "");
  EXPECT_NE(climb("newroom/a.cpp", "text/duration.hpp"), "");
}

}  // namespace
