// `model upload FILE` from the console against nlsoft-firmware-sim: a
// model the firmware can run goes in force and its hash is confirmed; a
// file it could not run is refused before anything is sent, and the model
// in force stays.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "host/files/cli_error.hpp"
#include "app/link/link_error.hpp"
#include "app/link/session.hpp"
#include "app/link/sim_launcher.hpp"
#include "app/live/live_console.hpp"
#include "app/script/script_parser.hpp"
#include "app/script/script_runner.hpp"
#include "shared/capacity.hpp"
#include "shared/crc32.hpp"
#include "shared/model_file.hpp"
#include "app/support/run_process.hpp"
#include "app/support/sim_console.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<uint8_t>& b) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

uint32_t trailing_crc(const std::vector<uint8_t>& b) {
  const size_t e = b.size() - 4;
  return uint32_t(b[e]) | uint32_t(b[e + 1]) << 8 | uint32_t(b[e + 2]) << 16 | uint32_t(b[e + 3]) << 24;
}

// The shipped model with its last weight nudged and the CRC made good
// again: a valid model with another hash.
std::vector<uint8_t> retrained(const std::string& platform) {
  std::vector<uint8_t> b = read_bytes(std::string(NLSOFT_SOURCE_MODELS_DIR) + "/" + platform + ".nlsm");
  if (b.size() < 32) return b;
  const size_t last = b.size() - 8;
  float v;
  std::memcpy(&v, &b[last], 4);
  v = v * 0.5f + 0.125f;
  std::memcpy(&b[last], &v, 4);
  const uint32_t crc = crc32(b.data(), b.size() - 4);
  for (int i = 0; i < 4; ++i) b[b.size() - 4 + size_t(i)] = uint8_t(crc >> (8 * i));
  return b;
}

class ModelUpload : public ::testing::Test {
 protected:
  void SetUp() override { console_ = test_support::connected_sim_console("msd", dir_); }
  uint32_t hash_in_force() { return console_->device().handshake().model_hash; }
  // The refusal's words, and proof the firmware still runs what it ran.
  std::string refusal(const std::string& path) {
    const uint32_t before = hash_in_force();
    std::string what;
    try {
      console_->model_upload().send(path);
    } catch (const CliError& e) {
      what = e.what();
    }
    EXPECT_EQ(hash_in_force(), before) << path;
    return what;
  }

  test::TempDir dir_;
  std::unique_ptr<LiveConsole> console_;
};

TEST_F(ModelUpload, ANewModelGoesInForceAndItsHashIsConfirmed) {
  const std::vector<uint8_t> model = retrained("msd");
  ASSERT_GT(model.size(), 32u);
  const std::string path = dir_.file("msd-retrained.nlsm");
  write_bytes(path, model);
  const uint32_t before = hash_in_force();
  ASSERT_NE(before, trailing_crc(model));

  size_t last_done = 0, last_total = 0, calls = 0;
  const auto r = console_->model_upload().send(path, [&](size_t d, size_t t) {
    EXPECT_GE(d, last_done) << "progress never goes back";
    last_done = d;
    last_total = t;
    ++calls;
  });
  EXPECT_EQ(r.previous_hash, before);
  EXPECT_EQ(r.hash, trailing_crc(model));
  EXPECT_EQ(r.bytes, model.size());
  EXPECT_GT(calls, 0u);
  EXPECT_EQ(last_done, last_total);
  EXPECT_EQ(last_total, model.size());
  EXPECT_EQ(hash_in_force(), trailing_crc(model)) << "the firmware runs the new model";
  EXPECT_EQ(console_->device().info().model_hash, trailing_crc(model)) << "runs record the new hash";
}

TEST_F(ModelUpload, TheScriptCommandUploadsAndSaysTheConfirmedHash) {
  const std::vector<uint8_t> model = retrained("msd");
  const std::string path = dir_.file("m.nlsm");
  write_bytes(path, model);
  std::vector<std::string> out;
  size_t progress_calls = 0;
  ScriptRunner runner(
      *console_, [&](const std::string& l) { out.push_back(l); },
      [&](const std::string& what, size_t, size_t) {
        if (what == "model " + path) ++progress_calls;
      });
  const Script s = parse_script("model upload " + path + "\nrun 1s\n", "t.nls");
  EXPECT_EQ(runner.run(s), 0);
  ASSERT_FALSE(out.empty());
  char hex[16];
  std::snprintf(hex, sizeof hex, "%08x", trailing_crc(model));
  EXPECT_NE(out[0].find(std::string("hash ") + hex + " confirmed"), std::string::npos) << out[0];
  EXPECT_GT(progress_calls, 0u);
  // The model's size in the words `model info` gives it, weights and
  // normalisation apart: one wording, not two counts that disagree.
  const auto info = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " model info " + path);
  ASSERT_EQ(info.code, 0) << info.output;
  const size_t at = info.output.find("parameters: ");
  ASSERT_NE(at, std::string::npos) << info.output;
  const std::string size = info.output.substr(at + 12, info.output.find('\n', at) - at - 12);
  EXPECT_NE(size.find(" weights + "), std::string::npos) << size;
  EXPECT_EQ(out[0].substr(out[0].size() - std::min(out[0].size(), size.size())), size) << out[0] << "\n" << info.output;
}

TEST_F(ModelUpload, FilesTheFirmwareCouldNotRunAreRefusedBeforeAnythingIsSent) {
  std::vector<uint8_t> damaged = retrained("msd");
  damaged[damaged.size() / 2] ^= 0x40;
  write_bytes(dir_.file("damaged.nlsm"), damaged);
  EXPECT_NE(refusal(dir_.file("damaged.nlsm")).find("bad checksum"), std::string::npos);

  write_bytes(dir_.file("hasel.nlsm"), read_bytes(std::string(NLSOFT_SOURCE_MODELS_DIR) + "/hasel.nlsm"));
  const std::string other = refusal(dir_.file("hasel.nlsm"));
  EXPECT_NE(other.find("m=6 n=3"), std::string::npos) << other;

  write_bytes(dir_.file("short.nlsm"), std::vector<uint8_t>(damaged.begin(), damaged.begin() + 40));
  EXPECT_NE(refusal(dir_.file("short.nlsm")).find("not a usable model file"), std::string::npos);

  EXPECT_NE(refusal(dir_.file("absent.nlsm")).find("cannot read"), std::string::npos);
}

TEST_F(ModelUpload, IsRefusedDuringARun) {
  write_bytes(dir_.file("m.nlsm"), retrained("msd"));
  console_->runs().start("model change mid-run");
  EXPECT_NE(refusal(dir_.file("m.nlsm")).find("stop the run first"), std::string::npos);
  console_->runs().stop();
}

// A valid model file of hasel's dimensions (36 inputs), zero weights,
// dense layers of these sizes.
std::vector<uint8_t> hasel_dense(std::vector<int> units) {
  const int m = 6, n = 3, w = 18, nd = 2, in0 = nd * (m + n) + w;
  uint32_t params = uint32_t(2 * in0 + 2 * n);
  int in = in0;
  for (int u : units) params += uint32_t(in * u + u), in = u;
  std::vector<uint8_t> f(model_file_size(int(units.size()), params));
  std::memcpy(f.data(), "NLSM", 4);
  namespace at = model_offset;
  f[at::kVersion] = kModelFormatVersion, f[at::kM] = m, f[at::kN] = n, f[at::kW] = w, f[at::kNd] = f[at::kDd] = nd;
  f[at::kLayers] = uint8_t(units.size()), f[at::kPlatform] = 1;
  for (int i = 0; i < 4; ++i) f[at::kParams + i] = uint8_t(params >> (8 * i));
  in = in0;
  for (size_t l = 0; l < units.size(); ++l) {
    uint8_t* e = f.data() + kModelHeaderSize + kModelLayerSize * l;
    e[0] = 1, e[4] = uint8_t(in), e[6] = uint8_t(units[l]);
    in = units[l];
  }
  const uint32_t crc = crc32(f.data(), f.size() - 4);
  for (int i = 0; i < 4; ++i) f[f.size() - 4 + i] = uint8_t(crc >> (8 * i));
  return f;
}

// What XFER_COMMIT of a model says on the firmware at `pty`: xfer_not_open
// when no model transfer was begun there, xfer_incomplete when one was.
std::string model_commit_status(Session& s) {
  protocol::XferCommit c;
  c.kind = uint8_t(protocol::XferKind::Model);
  try {
    s.call<protocol::Ack>(c);
    return "ack";
  } catch (const NackError& e) {
    return protocol::to_string(e.status());
  }
}

// Protocol 1.2: the console refuses a model of a shape the firmware does not
// accept (here wider than the simulator's generic kernel takes) before it
// sends a byte of it: the script fails with exit 2, and the simulator never
// saw an XFER_BEGIN (a BEGIN would have left a transfer open, which a COMMIT
// afterwards tells from none: the control below shows the difference).
TEST(ModelUploadShape, AModelOfARefusedShapeIsRefusedBeforeTheTransfer) {
  test::TempDir dir;
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  SimLauncher sim;
  const std::string pty = sim.start("hasel");
  ASSERT_FALSE(pty.empty());
  const auto wide = hasel_dense({HostCapacity::width + 1, 3});
  write_bytes(dir.file("wide.nlsm"), wide);
  std::ofstream(dir.file("up.nls")) << "model upload " << dir.file("wide.nlsm") << "\n";
  const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + pty + " --no-record --script " +
                                   dir.file("up.nls"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("wide.nlsm is Dense 36->49->3 (a layer 49 wide); this firmware (rig hasel) accepts any "
                          "shape within 8 layers, 48 wide"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("connected: nlsoft-posix 0.1.0, rig hasel,"), std::string::npos) << r.output;

  Session s;
  s.open(pty, 115200);
  EXPECT_EQ(model_commit_status(s), "xfer_not_open") << "the console sent an XFER_BEGIN";
  // Control: a BEGIN of the same file is taken by the simulator (its size is
  // within model_max; the header would be refused with the first chunk) and
  // shows in the COMMIT's answer.
  protocol::XferBegin b;
  b.kind = uint8_t(protocol::XferKind::Model);
  b.total_size = uint32_t(wide.size());
  b.crc32 = crc32(wide.data(), wide.size());
  s.call<protocol::XferAck>(b);
  EXPECT_EQ(model_commit_status(s), "xfer_incomplete");
}

// --rig names the rig file the board's image should come from: a firmware
// that names another rig is warned about, once; the same rig with no hash
// (an image not built from a rig file) is not.
TEST(ModelUploadShape, ARigOtherThanTheOneGivenIsWarnedAbout) {
  test::TempDir dir;
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  SimLauncher sim;
  const std::string pty = sim.start("hasel");
  ASSERT_FALSE(pty.empty());
  std::ofstream(dir.file("s.nls")) << "echo ok\n";
  const std::string cmd = std::string(NLSOFT_CONSOLE_BIN) + " " + pty + " --no-record --script " + dir.file("s.nls");
  const auto other = test::run_process(cmd + " --rig tendon");
  EXPECT_EQ(other.code, 0) << other.output;
  const size_t at = other.output.find("warning: the firmware runs rig hasel (hash ");
  EXPECT_NE(at, std::string::npos) << other.output;
  EXPECT_EQ(other.output.find("warning: the firmware runs rig", at + 1), std::string::npos) << "said once";
  const auto same = test::run_process(cmd + " --rig hasel");
  EXPECT_EQ(same.code, 0) << same.output;
  EXPECT_EQ(same.output.find("warning: the firmware"), std::string::npos) << same.output;
  const auto both = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --rig hasel --script " +
                                      dir.file("s.nls"));
  EXPECT_EQ(both.code, 2) << both.output;
  EXPECT_NE(both.output.find("--rig names the rig of a board given by PORT"), std::string::npos) << both.output;
}

TEST(ModelUploadScript, ParsesAndNamesItsUsage) {
  const Command c = parse_command("model upload a.nlsm", "t", 1);
  EXPECT_EQ(c.kind, Command::Kind::ModelUpload);
  EXPECT_EQ(c.name, "a.nlsm");
  EXPECT_THROW(parse_command("model upload", "t", 1), ScriptError);
  EXPECT_THROW(parse_command("model send a.nlsm", "t", 1), ScriptError);
  EXPECT_THROW(parse_command("model upload a.nlsm b", "t", 1), ScriptError);
}

}  // namespace
}  // namespace nlsoft::console
