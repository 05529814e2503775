// SETTINGS end to end on the simulator (PROTOCOL.md 9.11): a parameter saved
// with --settings FILE is in force after the simulator restarts, "defaults"
// brings the built-in value back, and a simulator without the file has no
// SETTINGS capability and refuses the request.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "peer.hpp"
#include "sim_process.hpp"

using namespace nlsoft;
using namespace nlsoft::test;

namespace {

std::string temp_file(const char* what) {
  return ::testing::TempDir() + "settings-" + what + "." + std::to_string(::getpid()) + ".bin";
}

// A simulator and a peer on its pty.
struct Sim {
  explicit Sim(std::vector<std::string> args) {
    args.insert(args.begin(), {NLSOFT_FIRMWARE_SIM, "--rig", "msd"});
    process = std::make_unique<SimProcess>(args);
    if (!process->path().empty()) peer = std::make_unique<Peer>(process->path());
  }
  bool ok() const { return peer && peer->ok(); }
  template <class M>
  Received must(const M& m, int timeout_ms = 1000) {
    auto r = peer->request(m, timeout_ms);
    EXPECT_TRUE(r.has_value()) << "no reply to " << proto::message_name(uint8_t(M::kType));
    return r.value_or(Received{});
  }
  uint32_t capabilities() { return as<proto::InfoEx>(must(proto::InfoGet{})).info.capabilities; }
  uint32_t n() {
    proto::ParamGet g;
    g.id = uint16_t(ParamId::N);
    return as<proto::ParamValue>(must(g)).values[0];
  }
  void set_n(uint32_t v) {
    proto::ParamSet p;
    p.id = uint16_t(ParamId::N), p.count = 1, p.values[0] = v;
    EXPECT_EQ(as<proto::ParamValue>(must(p)).values[0], v);
  }
  Received settings(proto::SettingsAction a) {
    proto::Settings s;
    s.action = uint8_t(a);
    return must(s, 1500);
  }
  // The next LOG that starts with "settings:", from what arrived so far or within a second.
  std::string settings_log() {
    auto is_settings = [](const Received& r) {
      if (r.header.type != uint8_t(proto::MsgType::Log)) return false;
      proto::Log g;
      return proto::unpack(r.view(), g) == proto::StatusCode::Ok && std::string(g.text).rfind("settings:", 0) == 0;
    };
    for (auto it = peer->unsolicited.begin(); it != peer->unsolicited.end(); ++it)
      if (is_settings(*it)) {
        const std::string text = as<proto::Log>(*it).text;
        peer->unsolicited.erase(it);
        return text;
      }
    auto r = peer->wait_for(is_settings, 1000);
    return r ? std::string(as<proto::Log>(*r).text) : "(no settings LOG)";
  }
  std::unique_ptr<SimProcess> process;
  std::unique_ptr<Peer> peer;
};

TEST(PosixSettings, ASavedParameterSurvivesARestartAndDefaultsBringTheBuiltInBack) {
  const std::string file = temp_file("restart");
  std::remove(file.c_str());
  uint32_t builtin = 0;
  {
    Sim sim({"--settings", file});
    ASSERT_TRUE(sim.ok());
    EXPECT_NE(sim.capabilities() & proto::capability::kSettings, 0u);
    EXPECT_EQ(sim.settings_log(), "settings: built-in (nothing saved)");
    builtin = sim.n();
    sim.set_n(builtin + 2);
    const Received r = sim.settings(proto::SettingsAction::Save);
    ASSERT_EQ(r.header.type, uint8_t(proto::MsgType::Ack));
    EXPECT_EQ(sim.settings_log().rfind("settings: saved to flash, save 1 (", 0), 0u);
  }
  {
    Sim sim({"--settings", file});
    ASSERT_TRUE(sim.ok());
    EXPECT_EQ(sim.n(), builtin + 2);
    EXPECT_EQ(sim.settings_log().rfind("settings: from flash, save 1 (", 0), 0u);
    ASSERT_EQ(sim.settings(proto::SettingsAction::Defaults).header.type, uint8_t(proto::MsgType::Ack));
    EXPECT_EQ(sim.n(), builtin);
  }
  {
    Sim sim({"--settings", file});
    ASSERT_TRUE(sim.ok());
    EXPECT_EQ(sim.n(), builtin);
    EXPECT_EQ(sim.settings_log(), "settings: built-in (restored by request)");
  }
  std::remove(file.c_str());
}

TEST(PosixSettings, WithoutASettingsFileTheRequestIsUnsupported) {
  Sim sim({});
  ASSERT_TRUE(sim.ok());
  EXPECT_EQ(sim.capabilities() & proto::capability::kSettings, 0u);
  const Received r = sim.settings(proto::SettingsAction::Save);
  ASSERT_EQ(r.header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(r).status, uint8_t(proto::StatusCode::Unsupported));
}

TEST(PosixSettings, AFileThatIsNotASettingsFileIsRefusedAtStart) {
  const std::string file = temp_file("wrong-size");
  std::ofstream(file) << "not two sectors";
  const std::string err = temp_file("stderr");
  const std::string command = std::string(NLSOFT_FIRMWARE_SIM) + " --rig msd --settings " + file + " >/dev/null 2>" + err;
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream in(err);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("--settings: settings file '" + file + "' is 15 bytes, not the 32768 of two 16 KiB sectors"),
            std::string::npos)
      << text;
  std::remove(file.c_str());
  std::remove(err.c_str());
}

}  // namespace
