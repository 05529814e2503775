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

#include "app/cli_error.hpp"
#include "app/live/live_console.hpp"
#include "app/script/script_parser.hpp"
#include "app/script/script_runner.hpp"
#include "shared/crc32.hpp"
#include "run_process.hpp"
#include "sim_console.hpp"
#include "temp_dir.hpp"

namespace nlsoft::console {
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
      console_->upload_model(path);
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
  const auto r = console_->upload_model(path, [&](size_t d, size_t t) {
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
  console_->start_run("model change mid-run");
  EXPECT_NE(refusal(dir_.file("m.nlsm")).find("stop the run first"), std::string::npos);
  console_->stop_run();
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
