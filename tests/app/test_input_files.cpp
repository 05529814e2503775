// What the console reads because a user named it (a model to upload or
// simulate, a script, a parameter file, a reference table, a dataset): a
// device, a directory or a file larger than such a file can be is refused
// in words before anything is read, exit 2; a FIFO still works for text.
// Each command runs as a user runs it, under `ulimit -v` so a console that
// did read /dev/zero fails here with bad_alloc instead of taking the
// machine's memory.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

// A sanitizer's shadow memory needs terabytes of address space, so its
// builds run the console without the limit (the refusals are asserted all
// the same; only the "no memory eaten" half needs the limit).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
const char* const kAddressLimit = "";
#else
const char* const kAddressLimit = "ulimit -v 2097152; ";
#endif

using test::run_process;
using test::shell_quote;

class InputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
    ASSERT_EQ(::mkdir(dir_.file("folder").c_str(), 0755), 0);
    // 64 MiB without the disk space: larger than any model or script.
    std::ofstream(dir_.file("huge"));
    ASSERT_EQ(::truncate(dir_.file("huge").c_str(), 64 << 20), 0);
  }
  // dash's ulimit -v counts KiB: 2 GiB of address space.
  test::ProcessResult console(const std::string& args) const {
    return run_process(kAddressLimit + std::string(NLSOFT_CONSOLE_BIN) + " " + args);
  }
  test::ProcessResult script(const std::string& text) const {
    std::ofstream(dir_.file("s.nls")) << text;
    return console("--sim msd --db " + shell_quote(dir_.file("runs.db")) + " --script " + shell_quote(dir_.file("s.nls")));
  }
  test::TempDir dir_;
};

TEST_F(InputFiles, AModelUploadRefusesDevicesFoldersAndWhatTheFirmwareCannotTake) {
  auto r = script("model upload /dev/zero\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "cannot read /dev/zero: it is a character device, not a model file")) << r.output;

  r = script("model upload " + dir_.file("folder") + "\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a directory, not a model file")) << r.output;

  r = script("model upload " + dir_.file("huge") + "\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "64.0 MiB; this firmware takes models of at most")) << r.output;
}

TEST_F(InputFiles, ScriptsParameterFilesAndReferenceTablesAreBoundedToo) {
  auto r = console("--sim msd --script /dev/zero");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a character device, not a script")) << r.output;
  r = console("--sim msd --script " + shell_quote(dir_.file("folder")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a directory, not a script")) << r.output;
  r = console("--sim msd --script " + shell_quote(dir_.file("huge")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "64.0 MiB; a script is at most 4.0 MiB")) << r.output;

  r = script("params load /dev/zero\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a character device, not a parameter file")) << r.output;
  r = script("ref load /dev/zero\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a character device, not a reference table CSV")) << r.output;
  r = script("ref load " + dir_.file("folder") + "\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a directory")) << r.output;
}

TEST_F(InputFiles, TheModelPipelineAndTheSimulatorRefuseThemAlike) {
  auto r = console("simulate --platform msd --model /dev/zero");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a character device, not a model file")) << r.output;
  r = console("model info " + shell_quote(dir_.file("folder")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a directory, not a model file")) << r.output;
  r = console("model info " + shell_quote(dir_.file("huge")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "64.0 MiB; a model file is at most")) << r.output;
  r = console("train --platform msd --data /dev/zero --out " + shell_quote(dir_.file("m.nlsm")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a character device, not a CSV file")) << r.output;
  r = console("model import " + shell_quote(dir_.file("folder")) + " --out " + shell_quote(dir_.file("m.nlsm")));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "it is a directory, not a Keras HDF5 file")) << r.output;
}

// A script from a FIFO, as `--script <(generate)` gives one: still read.
TEST_F(InputFiles, AScriptFromAFifoIsStillRead) {
  const std::string fifo = dir_.file("script.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto r = run_process("printf 'get Q\\n' > " + shell_quote(fifo) + " & " + std::string(NLSOFT_CONSOLE_BIN) +
                             " --sim msd --db " + shell_quote(dir_.file("runs.db")) + " --script " + shell_quote(fifo) +
                             "; s=$?; wait; exit $s");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "Q")) << r.output;
}

}  // namespace
}  // namespace nlsoft::console
