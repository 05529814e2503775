// The services a rig file's [firmware] features leave out, on the simulator
// (built with all of them, it serves what the file asks for): INFO has
// none of their capability bits, INFO_EX none of their sizes, and each of
// their requests is refused `unsupported` (PROTOCOL.md 9.12), while the
// minimum (parameters, a closed-loop run, telemetry) works as before.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "peer.hpp"
#include "sim_process.hpp"

using namespace nlsoft;
using namespace nlsoft::test;
namespace cap = proto::capability;

namespace {

std::string temp_path(const std::string& what) {
  return ::testing::TempDir() + "features-" + what + "." + std::to_string(::getpid());
}

// msd's shipped rig file with a [firmware] table of `features`.
std::string msd_with(const std::string& features) {
  std::ifstream in(NLSOFT_ROOT "/rigs/msd.toml");
  std::stringstream text;
  text << in.rdbuf();
  const std::string path = temp_path("msd") + ".toml";
  std::ofstream(path) << text.str() << "\n[firmware]\nfeatures = " << features << "\n";
  return path;
}

struct FeatureSim {
  explicit FeatureSim(const std::string& rig, const std::string& settings) {
    process = std::make_unique<SimProcess>(
        std::vector<std::string>{NLSOFT_FIRMWARE_SIM, "--rig", rig, "--settings", settings});
    if (!process->path().empty()) peer = std::make_unique<Peer>(process->path());
  }
  bool ok() const { return peer && peer->ok(); }
  template <class M>
  Received must(const M& m) {
    auto r = peer->request(m, 1500);
    EXPECT_TRUE(r.has_value()) << "no reply to " << proto::message_name(uint8_t(M::kType));
    return r.value_or(Received{});
  }
  // The status of the NACK `m` gets; -1 when it is answered otherwise.
  template <class M>
  int refusal(const M& m) {
    const Received r = must(m);
    if (r.header.type != uint8_t(proto::MsgType::Nack)) return -1;
    return as<proto::Nack>(r).status;
  }
  std::unique_ptr<SimProcess> process;
  std::unique_ptr<Peer> peer;
};

proto::XferBegin begin_of(proto::XferKind kind) {
  proto::XferBegin b;
  b.kind = uint8_t(kind);
  b.total_size = 64;
  return b;
}

TEST(PosixFeatures, TheMinimumRefusesEveryServiceItLeavesOutAndStillRuns) {
  const std::string settings = temp_path("flash");
  std::remove(settings.c_str());
  FeatureSim sim(msd_with("[]"), settings);
  ASSERT_TRUE(sim.ok());
  const auto ex = as<proto::InfoEx>(sim.must(proto::InfoGet{}));
  const uint32_t caps = ex.info.capabilities;
  for (uint32_t bit : {cap::kIdent, cap::kIdentMixed, cap::kXferModel, cap::kXferRefTable, cap::kSettings})
    EXPECT_FALSE(caps & bit) << "capability bit " << bit;
  for (uint32_t bit : {cap::kParams, cap::kRefBuiltin, cap::kTelemetry, cap::kRunHold, cap::kLog, cap::kRig})
    EXPECT_TRUE(caps & bit) << "capability bit " << bit;
  EXPECT_EQ(ex.table_max, 0u);
  EXPECT_EQ(ex.model_max, 0u);

  const int unsupported = int(proto::StatusCode::Unsupported);
  proto::IdentStart ident;
  ident.run_id = 5, ident.amplitude = 0.5f, ident.band_lo = 1, ident.band_hi = 10, ident.duration = 100;
  EXPECT_EQ(sim.refusal(ident), unsupported);
  EXPECT_EQ(sim.refusal(begin_of(proto::XferKind::Model)), unsupported);
  EXPECT_EQ(sim.refusal(begin_of(proto::XferKind::RefTable)), unsupported);
  for (proto::XferKind kind : {proto::XferKind::Model, proto::XferKind::RefTable}) {
    proto::XferChunk chunk;
    chunk.kind = uint8_t(kind), chunk.size = 4;
    EXPECT_EQ(sim.refusal(chunk), unsupported);
    proto::XferCommit commit;
    commit.kind = uint8_t(kind);
    EXPECT_EQ(sim.refusal(commit), unsupported);
    proto::XferAbort abort;  // an abort of what is not open is ACKed, as ever
    abort.kind = uint8_t(kind);
    EXPECT_EQ(sim.must(abort).header.type, uint8_t(proto::MsgType::Ack));
  }
  proto::XferBegin other = begin_of(proto::XferKind::Model);
  other.kind = 9;  // a kind the protocol does not have stays unknown_id
  EXPECT_EQ(sim.refusal(other), int(proto::StatusCode::UnknownId));
  proto::Settings save;
  save.action = uint8_t(proto::SettingsAction::Save);
  EXPECT_EQ(sim.refusal(save), unsupported);

  // The minimum: a run on the compiled-in reference, with telemetry.
  proto::RunStart start;
  start.run_id = 7;
  ASSERT_EQ(sim.must(start).header.type, uint8_t(proto::MsgType::Ack));
  auto t = sim.peer->wait_for([](const Received& r) { return r.header.type == uint8_t(proto::MsgType::Telemetry); },
                              2000);
  EXPECT_TRUE(t.has_value()) << "no telemetry from a run of the minimal firmware";
  EXPECT_EQ(sim.must(proto::RunStop{}).header.type, uint8_t(proto::MsgType::Ack));
  std::remove(settings.c_str());
}

TEST(PosixFeatures, AListedServiceIsServedAndOnlyThat) {
  const std::string settings = temp_path("flash-some");
  std::remove(settings.c_str());
  FeatureSim sim(msd_with("[\"settings\", \"table-upload\"]"), settings);
  ASSERT_TRUE(sim.ok());
  const auto ex = as<proto::InfoEx>(sim.must(proto::InfoGet{}));
  EXPECT_TRUE(ex.info.capabilities & cap::kSettings);
  EXPECT_TRUE(ex.info.capabilities & cap::kXferRefTable);
  EXPECT_GT(ex.table_max, 0u);
  EXPECT_FALSE(ex.info.capabilities & cap::kXferModel);
  EXPECT_FALSE(ex.info.capabilities & cap::kIdent);
  proto::Settings save;
  save.action = uint8_t(proto::SettingsAction::Save);
  EXPECT_EQ(sim.must(save).header.type, uint8_t(proto::MsgType::Ack));
  EXPECT_EQ(sim.refusal(begin_of(proto::XferKind::Model)), int(proto::StatusCode::Unsupported));
  std::remove(settings.c_str());
}

}  // namespace
