// The posix firmware over a real pty, driven as the console drives it.
#include <gtest/gtest.h>

#include <algorithm>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "firmware/core/firmware.hpp"
#include "peer.hpp"
#include "shared/capacity.hpp"
#include "shared/crc32.hpp"
#include "shared/model_file.hpp"
#include "shared/params.hpp"
#include "sim_process.hpp"
#include "support/msd_arx_model.hpp"

using namespace nlsoft;
using namespace nlsoft::test;
namespace tf = proto::telemetry_field;

namespace {

// One file per test process: ctest runs each test as a process of its own,
// in parallel, and a shared name would be truncated by one while another's
// simulator reads it ("no model for msd").
std::string model_path() {
  static std::string path;
  if (path.empty()) {
    path = ::testing::TempDir() + "msd_arx." + std::to_string(::getpid()) + ".nlsm";
    const auto file = msd_arx_model_file();
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(file.data()), long(file.size()));
  }
  static const struct RemoveAtExit {
    ~RemoveAtExit() { std::remove(path.c_str()); }
  } remove_at_exit;
  return path;
}


// The three messages of a model transfer that fits one chunk.
struct ModelXfer {
  proto::XferBegin begin;
  proto::XferChunk chunk;
  proto::XferCommit commit;
};
ModelXfer model_xfer(const std::vector<uint8_t>& file) {
  ModelXfer x;
  x.begin.kind = x.chunk.kind = x.commit.kind = uint8_t(proto::XferKind::Model);
  x.begin.total_size = uint32_t(file.size());
  x.begin.crc32 = crc32(file.data(), file.size());
  x.chunk.size = uint8_t(file.size());
  std::memcpy(x.chunk.data, file.data(), file.size());
  return x;
}

// PARAM_SET watchdog_ms 0: the peer only listens while a run goes.
proto::ParamSet watchdog_off() {
  proto::ParamSet wd;
  wd.id = uint16_t(fw::FwParamId::WatchdogMs);
  wd.count = 1;
  wd.values[0] = 0;
  return wd;
}

// IDENT_START of a PRBS over each input's whole range, 1-20 Hz, every step sampled.
proto::IdentStart prbs_ident(uint32_t run_id, uint32_t seed, uint32_t steps) {
  proto::IdentStart start;
  start.run_id = run_id;
  start.signal = uint8_t(proto::IdentSignal::Prbs);
  start.decimation = 1;
  start.seed = seed;
  start.amplitude = 1.0f;
  start.band_lo = 1.0f;
  start.band_hi = 20.0f;
  start.duration = steps;
  return start;
}

// The identification run's samples as they arrive, until `steps` or until
// none comes for 2 s.
std::vector<proto::IdentSample> ident_samples(Peer& peer, uint32_t steps) {
  std::vector<proto::IdentSample> s;
  while (s.size() < steps) {
    auto r = peer.wait_for([](const Received& x) { return x.header.type == uint8_t(proto::MsgType::IdentSample); },
                           2000);
    if (!r) break;
    for (auto& u : peer.unsolicited)
      if (u.header.type == uint8_t(proto::MsgType::IdentSample)) s.push_back(as<proto::IdentSample>(u));
    peer.unsolicited.clear();
    s.push_back(as<proto::IdentSample>(*r));
  }
  return s;
}

class PosixFirmware : public ::testing::Test {
 protected:
  void SetUp() override {
    sim_ = std::make_unique<SimProcess>(
        std::vector<std::string>{NLSOFT_FIRMWARE_SIM, "--platform", "msd", "--fast", "--model", model_path()});
    ASSERT_FALSE(sim_->path().empty()) << "the simulator printed no pty path";
    peer_ = std::make_unique<Peer>(sim_->path());
    ASSERT_TRUE(peer_->ok());
  }
  Received must(std::optional<Received> r, const char* what) {
    EXPECT_TRUE(r.has_value()) << "no reply to " << what;
    return r.value_or(Received{});
  }
  std::unique_ptr<SimProcess> sim_;
  std::unique_ptr<Peer> peer_;
};

}  // namespace

// Idle, the simulator blocks in ppoll until its port has bytes: no read()
// that finds nothing (EAGAIN), where it used to try its port some 11,000
// times a second, a fifth of a core. strace counts the reads over a second
// of idling.
TEST(PosixFirmwareIdle, AnIdleSimulatorMakesNoFailingReads) {
  const char* strace = "/usr/bin/strace";
  ASSERT_EQ(::access(strace, X_OK), 0) << "strace is needed (bash cmake/dev deps installs it)";
  const std::string trace = ::testing::TempDir() + "sim-reads." + std::to_string(::getpid()) + ".txt";
  // `timeout` ends the simulator after a second of idling, and strace with it.
  const std::string command = std::string(strace) + " -f -qq -e trace=read -o " + trace + " timeout -s TERM 1 " +
                              NLSOFT_FIRMWARE_SIM + " --platform msd --model " + model_path() + " >/dev/null 2>&1";
  ASSERT_NE(std::system(command.c_str()), -1);
  std::ifstream in(trace);
  size_t reads = 0, failed = 0;
  std::string first_failed;
  for (std::string line; std::getline(in, line);) {
    if (line.find("read(") == std::string::npos) continue;
    ++reads;
    if (line.find("EAGAIN") != std::string::npos && failed++ == 0) first_failed = line;
  }
  std::remove(trace.c_str());
  EXPECT_GT(reads, 0u) << "strace saw no read at all (the model file is read with read())";
  EXPECT_EQ(failed, 0u) << failed << " of " << reads << " reads found nothing, e.g. " << first_failed;
}

TEST_F(PosixFirmware, HandshakeReportsPlatformModelAndTable) {
  const Received r = must(peer_->request(proto::InfoGet{}), "INFO_GET");
  ASSERT_EQ(r.header.type, uint8_t(proto::MsgType::InfoEx));
  const auto ex = as<proto::InfoEx>(r);
  const proto::Info& info = ex.info;
  EXPECT_EQ(ex.protocol_minor, proto::kProtocolMinor);
  EXPECT_EQ(info.platform, uint8_t(PlatformId::Msd));
  EXPECT_EQ(info.m, 1);
  EXPECT_EQ(info.n, 1);
  EXPECT_EQ(info.w, 0);
  EXPECT_EQ(info.loop_rate_hz, 1000u);
  const auto file = msd_arx_model_file();
  EXPECT_EQ(info.model_hash, crc32(file.data(), file.size() - 4));
  EXPECT_TRUE(info.capabilities & proto::capability::kYTrue);
  // The posix port's buffers: 20000 points of 3 floats, the largest model
  // of the host capacity.
  EXPECT_EQ(ex.table_max, 8u + 4u * 3u * 20000u);
  EXPECT_EQ(ex.model_max, model_file_max<HostCapacity>());

  // param_hash is the CRC-32 of the PARAM_DESC payloads as they arrive.
  Crc32 crc;
  uint16_t count = 1;
  for (uint16_t i = 0; i < count; ++i) {
    proto::ParamList l;
    l.index = i;
    const Received d = must(peer_->request(l), "PARAM_LIST");
    ASSERT_EQ(d.header.type, uint8_t(proto::MsgType::ParamDesc));
    count = as<proto::ParamDesc>(d).count;
    crc.update(d.payload.data(), d.payload.size());
  }
  EXPECT_EQ(info.param_hash, crc.value());
}

// Protocol 1.2: the simulator's generic kernel takes any shape within the
// host capacity's limits, and says so; it names the rig file it serves.
TEST_F(PosixFirmware, RigInfoNamesThePlatformAndTakesAnyShapeWithinLimits) {
  const auto ex = as<proto::InfoEx>(must(peer_->request(proto::InfoGet{}), "INFO_GET"));
  ASSERT_TRUE(ex.info.capabilities & proto::capability::kRig);
  const Received r = must(peer_->request(proto::RigGet{}), "RIG_GET");
  ASSERT_EQ(r.header.type, uint8_t(proto::MsgType::RigInfo));
  const auto rig = as<proto::RigInfo>(r);
  EXPECT_STREQ(rig.rig_name, "msd");
  EXPECT_NE(rig.rig_hash, 0u) << "the simulator serves a rig file: its hash";
  EXPECT_EQ(rig.m, ex.info.m);
  EXPECT_EQ(rig.n, ex.info.n);
  EXPECT_EQ(rig.w, ex.info.w);
  EXPECT_EQ(rig.nd, ex.info.nd);
  EXPECT_EQ(rig.accept, proto::shape_accept::kAny);
  EXPECT_EQ(rig.shapes_size, 0);
  EXPECT_EQ(rig.max_layers, HostCapacity::layers);
  EXPECT_EQ(rig.max_width, HostCapacity::width);
  EXPECT_EQ(rig.max_weights, uint32_t(HostCapacity::weights));
}

// A layer wider than max_width: the size is within model_max, so BEGIN takes
// it; the first chunk brings the header and is refused, the transfer
// discarded, the built-in model still in force.
TEST_F(PosixFirmware, AModelWiderThanTheLimitIsRefusedAtItsFirstChunk) {
  const int units = HostCapacity::width + 1, p = 4;  // msd: nd (m + n) + w = 4
  const uint32_t params = uint32_t(2 * p + 2 + p * units + units + units + 1);
  std::vector<uint8_t> f(model_file_size(2, params));
  std::memcpy(f.data(), "NLSM", 4);
  f[model_offset::kVersion] = 1, f[model_offset::kM] = 1, f[model_offset::kN] = 1;
  f[model_offset::kNd] = f[model_offset::kDd] = 2, f[model_offset::kLayers] = 2;
  for (int i = 0; i < 4; ++i) f[model_offset::kParams + i] = uint8_t(params >> (8 * i));
  const uint8_t layers[] = {1, 2, 0, 0, 4, 0, uint8_t(units), 0, 1, 0, 0, 0, uint8_t(units), 0, 1, 0};
  std::memcpy(f.data() + kModelHeaderSize, layers, sizeof layers);
  const uint32_t crc = crc32(f.data(), f.size() - 4);
  for (int i = 0; i < 4; ++i) f[f.size() - 4 + i] = uint8_t(crc >> (8 * i));
  const auto before = as<proto::InfoEx>(must(peer_->request(proto::InfoGet{}), "INFO_GET")).info.model_hash;

  proto::XferBegin b;
  b.kind = uint8_t(proto::XferKind::Model);
  b.total_size = uint32_t(f.size());
  b.crc32 = crc32(f.data(), f.size());
  ASSERT_EQ(must(peer_->request(b), "XFER_BEGIN").header.type, uint8_t(proto::MsgType::XferAck));
  proto::XferChunk c;
  c.kind = b.kind;
  c.size = proto::kMaxChunkData;
  std::memcpy(c.data, f.data(), c.size);
  const Received n = must(peer_->request(c), "XFER_CHUNK");
  ASSERT_EQ(n.header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(n).status, uint8_t(proto::StatusCode::Unsupported));
  EXPECT_EQ(as<proto::Nack>(n).field, 2);
  c.offset = c.size;
  const Received gone = must(peer_->request(c), "XFER_CHUNK after the refusal");
  ASSERT_EQ(gone.header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(gone).status, uint8_t(proto::StatusCode::XferNotOpen));
  EXPECT_EQ(as<proto::InfoEx>(must(peer_->request(proto::InfoGet{}), "INFO_GET")).info.model_hash, before);
}

TEST_F(PosixFirmware, TooLargeTransfersAreRefusedAtTheAdvertisedLimit) {
  const auto ex = as<proto::InfoEx>(must(peer_->request(proto::InfoGet{}), "INFO_GET"));
  proto::XferBegin b;
  b.kind = uint8_t(proto::XferKind::RefTable);
  b.options = proto::xfer_options::kRestart;
  b.total_size = ex.table_max + 1;
  const auto n = as<proto::Nack>(must(peer_->request(b), "XFER_BEGIN too large"));
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::TooLarge));
  EXPECT_EQ(n.field, 2);
  b.total_size = ex.table_max;
  EXPECT_EQ(must(peer_->request(b), "XFER_BEGIN at the limit").header.type, uint8_t(proto::MsgType::XferAck));
}

TEST_F(PosixFirmware, RefSelectRefusalsNameTheFieldOverTheWire) {
  proto::RefSelect sel;
  sel.ref_id = uint8_t(proto::RefId::Infinity);
  sel.a = sel.b = sel.c = 1.0f;
  sel.omega = 0.01f;
  sel.center[2] = std::numeric_limits<float>::infinity();
  const auto n = as<proto::Nack>(must(peer_->request(sel), "REF_SELECT"));
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::NotFinite));
  EXPECT_EQ(n.field, 6);
  EXPECT_EQ(n.element, 2);
  // A NaN where infinity reads nothing (lambda) is ignored.
  sel.center[2] = 0.0f;
  sel.lambda = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(must(peer_->request(sel), "REF_SELECT").header.type, uint8_t(proto::MsgType::Ack));
  const auto st = as<proto::Status>(must(peer_->request(proto::StatusGet{}), "STATUS_GET"));
  EXPECT_EQ(st.ref_id, uint8_t(proto::RefId::Infinity));
}

TEST_F(PosixFirmware, AReusedSeqWithANewRequestIsExecuted) {
  // A console restarted at the same seq sends RUN_START for another run:
  // executed (refused, a run is active), not answered with the first ACK.
  auto send = [&](uint32_t run_id) {
    proto::RunStart m;
    m.run_id = run_id;
    uint8_t wire[proto::kWireBufferSize];
    const size_t len = proto::encode(m, 200, 0, wire, sizeof wire);
    peer_->send_raw(wire, len);
    return peer_->wait_for([](const Received& r) { return r.header.seq == 200 && r.header.flags == 1; }, 1000);
  };
  const auto first = send(11);
  ASSERT_TRUE(first.has_value());
  ASSERT_EQ(first->header.type, uint8_t(proto::MsgType::Ack));
  const auto twin = send(11);  // a retransmission: the stored ACK
  ASSERT_TRUE(twin.has_value());
  EXPECT_EQ(twin->header.type, uint8_t(proto::MsgType::Ack));
  const auto other = send(12);
  ASSERT_TRUE(other.has_value());
  ASSERT_EQ(other->header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(*other).status, uint8_t(proto::StatusCode::WrongState));
  const auto st = as<proto::Status>(must(peer_->request(proto::StatusGet{}), "STATUS_GET"));
  EXPECT_EQ(st.run_id, 11u);
}

TEST_F(PosixFirmware, ParameterRoundTripAndRefusals) {
  // the list describes every parameter, table first
  const uint16_t count = fw::ParamService<HostCapacity>::count();
  for (uint16_t i = 0; i < count; ++i) {
    proto::ParamList l;
    l.index = i;
    const auto d = as<proto::ParamDesc>(must(peer_->request(l), "PARAM_LIST"));
    EXPECT_EQ(d.count, count);
    if (i < uint16_t(ParamId::Count)) {
      EXPECT_STREQ(d.name, kParamTable[i].name);
    }
  }
  proto::ParamList past;
  past.index = count;
  EXPECT_EQ(must(peer_->request(past), "PARAM_LIST past the end").header.type, uint8_t(proto::MsgType::Nack));

  auto v = as<proto::ParamValue>(must(peer_->request(param_set(ParamId::Lambda, {0.05f})), "PARAM_SET"));
  EXPECT_FLOAT_EQ(v.f32(0), 0.05f);

  const Received nan = must(peer_->request(param_set(ParamId::Q, {std::nanf("")})), "PARAM_SET NaN");
  ASSERT_EQ(nan.header.type, uint8_t(proto::MsgType::Nack));
  const auto n = as<proto::Nack>(nan);
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::NotFinite));
  EXPECT_EQ(n.field, 1);
  EXPECT_EQ(n.element, 0);
  const auto wrong = as<proto::Nack>(must(peer_->request(param_set(ParamId::Q, {1.0f, 2.0f})), "PARAM_SET 2 values"));
  EXPECT_EQ(wrong.status, uint8_t(proto::StatusCode::WrongSize));

  proto::ParamGet g;
  g.id = uint16_t(ParamId::Q);
  v = as<proto::ParamValue>(must(peer_->request(g), "PARAM_GET"));
  EXPECT_FLOAT_EQ(v.f32(0), 1.0f);  // the preset's Q, untouched by the refusals
}

TEST_F(PosixFirmware, RunTracksAStepAndLosesNoTelemetry) {
  // This test only listens while the run goes; on a slow machine (a
  // sanitizer build) reading 2000 frames takes longer than the link
  // watchdog's second, which would stop the run: the watchdog is off here.
  proto::ParamSet wd;
  wd.id = uint16_t(fw::FwParamId::WatchdogMs);
  wd.count = 1;
  wd.values[0] = 0;
  ASSERT_EQ(must(peer_->request(wd), "PARAM_SET watchdog_ms").header.type, uint8_t(proto::MsgType::ParamValue));
  proto::RefSelect ref;
  ref.ref_id = uint8_t(proto::RefId::Step);
  ref.level_count = 1;
  ref.hold = 60000;
  ref.levels[0] = 0.5f;
  ASSERT_EQ(must(peer_->request(ref), "REF_SELECT").header.type, uint8_t(proto::MsgType::Ack));
  proto::TelemetryConfig tc;
  tc.mask = tf::kAll;
  tc.decimation = 1;
  ASSERT_EQ(must(peer_->request(tc), "TELEMETRY_CONFIG").header.type, uint8_t(proto::MsgType::Ack));
  proto::RunStart start;
  start.run_id = 7;
  ASSERT_EQ(must(peer_->request(start), "RUN_START").header.type, uint8_t(proto::MsgType::Ack));

  // 2 simulated seconds of telemetry (fast mode: as fast as we read)
  std::vector<proto::Telemetry> t;
  while (t.size() < 2000) {
    auto r = peer_->wait_for([](const Received& x) { return x.header.type == uint8_t(proto::MsgType::Telemetry); },
                             2000);
    ASSERT_TRUE(r.has_value()) << "telemetry stopped after " << t.size() << " frames";
    for (auto& u : peer_->unsolicited)
      if (u.header.type == uint8_t(proto::MsgType::Telemetry)) t.push_back(as<proto::Telemetry>(u));
    peer_->unsolicited.clear();
    t.push_back(as<proto::Telemetry>(*r));
  }
  ASSERT_EQ(must(peer_->request(proto::RunStop{}), "RUN_STOP").header.type, uint8_t(proto::MsgType::Ack));

  long lost = 0;
  for (size_t i = 1; i < t.size(); ++i) lost += uint16_t(t[i].tseq - t[i - 1].tseq - 1);
  EXPECT_EQ(lost, 0);
  EXPECT_EQ(t.front().step, 0u);
  for (size_t i = 1; i < t.size(); ++i) ASSERT_EQ(t[i].step, t[i - 1].step + 1);
  const proto::Telemetry& last = t.back();
  EXPECT_FLOAT_EQ(last.y_ref[0], 0.5f);
  EXPECT_NEAR(last.y_true[0], 0.5f, 0.025f) << "y_true does not follow the reference";
  EXPECT_TRUE(std::isfinite(last.u[0]));
  EXPECT_GE(last.iterations, 1);
}

TEST_F(PosixFirmware, GarbageAndFloodsNeverStallTheLoop) {
  proto::RunStart start;
  start.run_id = 1;
  ASSERT_TRUE(peer_->request(start).has_value());
  std::mt19937 rng(3);
  std::vector<uint8_t> junk(20000);
  for (auto& b : junk) b = uint8_t(rng());
  peer_->send_raw(junk.data(), junk.size());
  const uint8_t zero = 0;
  peer_->send_raw(&zero, 1);
  // a flood of valid requests faster than any loop period
  for (int i = 0; i < 200; ++i) peer_->send(proto::StatusGet{});
  proto::Ping ping;
  ping.nonce = 0xC0FFEE;
  const auto pong = peer_->request(ping, 3000);
  ASSERT_TRUE(pong.has_value()) << "the firmware stopped answering after garbage";
  EXPECT_EQ(as<proto::Pong>(*pong).nonce, 0xC0FFEEu);
  const auto st = as<proto::Status>(must(peer_->request(proto::StatusGet{}), "STATUS_GET"));
  EXPECT_GT(st.crc_errors + st.frame_errors, 0u);
  EXPECT_EQ(st.run_state, uint8_t(proto::RunState::Running));
  EXPECT_GT(st.step, 0u);
  EXPECT_GT(st.compute_max, 0u);
  EXPECT_EQ(st.tick_rate_hz, 1000000u);
}

TEST_F(PosixFirmware, InterruptedTableUploadKeepsThePreviousTable) {
  // one point per 4 bytes; 200 points of n = 1
  std::vector<uint8_t> obj(8 + 4 * 200);
  obj[0] = 1, obj[1] = 1;
  const uint32_t count = 200;
  std::memcpy(&obj[4], &count, 4);
  for (uint32_t i = 0; i < count; ++i) {
    const float v = 0.001f * float(i);
    std::memcpy(&obj[8 + 4 * i], &v, 4);
  }
  auto upload = [&](const std::vector<uint8_t>& o, uint32_t crc, bool skip_one) {
    proto::XferBegin b;
    b.kind = uint8_t(proto::XferKind::RefTable);
    b.total_size = uint32_t(o.size());
    b.crc32 = crc;
    b.options = proto::xfer_options::kRestart;
    EXPECT_EQ(must(peer_->request(b), "XFER_BEGIN").header.type, uint8_t(proto::MsgType::XferAck));
    uint32_t off = 0;
    bool skipped = false;
    while (off < o.size()) {
      proto::XferChunk c;
      c.kind = b.kind;
      c.offset = off;
      c.size = uint8_t(std::min<size_t>(200, o.size() - off));
      std::memcpy(c.data, &o[off], c.size);
      if (skip_one && !skipped && off > 0) {  // a lost chunk: send the one after it
        skipped = true;
        c.offset = off + 200;
        c.size = uint8_t(std::min<size_t>(200, o.size() - c.offset));
        std::memcpy(c.data, &o[c.offset], c.size);
      }
      const auto ack = as<proto::XferAck>(must(peer_->request(c), "XFER_CHUNK"));
      off = ack.next_offset;  // the firmware says where to continue
    }
    proto::XferCommit cm;
    cm.kind = b.kind;
    return must(peer_->request(cm), "XFER_COMMIT");
  };
  const uint32_t good = crc32(obj.data(), obj.size());
  EXPECT_EQ(upload(obj, good, true).header.type, uint8_t(proto::MsgType::Ack));
  proto::RefSelect sel;
  sel.ref_id = uint8_t(proto::RefId::Table);
  sel.hold = 1;
  EXPECT_EQ(must(peer_->request(sel), "REF_SELECT table").header.type, uint8_t(proto::MsgType::Ack));
  // a corrupted object: refused, the committed table stays selectable
  auto bad = obj;
  bad[100] ^= 0xFF;
  const auto nack = upload(bad, good, false);
  ASSERT_EQ(nack.header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(nack).status, uint8_t(proto::StatusCode::BadChecksum));
  EXPECT_EQ(must(peer_->request(sel), "REF_SELECT table").header.type, uint8_t(proto::MsgType::Ack));
}

TEST_F(PosixFirmware, ModelUploadOnlyWhileStopped) {
  const auto file = msd_arx_model_file();
  const ModelXfer x = model_xfer(file);
  ASSERT_EQ(must(peer_->request(x.begin), "XFER_BEGIN").header.type, uint8_t(proto::MsgType::XferAck));
  ASSERT_EQ(as<proto::XferAck>(must(peer_->request(x.chunk), "XFER_CHUNK")).next_offset, file.size());
  proto::RunStart start;
  start.run_id = 3;
  ASSERT_EQ(must(peer_->request(start), "RUN_START").header.type, uint8_t(proto::MsgType::Ack));
  const proto::XferCommit cm = x.commit;
  const auto busy = must(peer_->request(cm), "XFER_COMMIT while running");
  ASSERT_EQ(busy.header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(busy).status, uint8_t(proto::StatusCode::WrongState));
  ASSERT_EQ(must(peer_->request(proto::RunStop{}), "RUN_STOP").header.type, uint8_t(proto::MsgType::Ack));
  proto::XferCommit cm2 = cm;
  EXPECT_EQ(must(peer_->request(cm2), "XFER_COMMIT").header.type, uint8_t(proto::MsgType::Ack));
}

// The model in force is read where its file lies: an uploaded one in the
// transfer buffer, so a new model transfer first puts the built-in back.
TEST_F(PosixFirmware, ANewModelTransferPutsTheBuiltInModelBackUntilCommitted) {
  const auto builtin = msd_arx_model_file();
  auto other = builtin;
  other[kModelHeaderSize + kModelLayerSize + 4 * 9] ^= 0x01;  // one weight's lowest bit
  const uint32_t body = uint32_t(other.size() - 4);
  const uint32_t crc = crc32(other.data(), body);
  for (int i = 0; i < 4; ++i) other[body + i] = uint8_t(crc >> (8 * i));
  auto model_hash = [&] { return as<proto::InfoEx>(must(peer_->request(proto::InfoGet{}), "INFO_GET")).info.model_hash; };
  const uint32_t builtin_hash = crc32(builtin.data(), builtin.size() - 4);
  ASSERT_EQ(model_hash(), builtin_hash);

  const ModelXfer x = model_xfer(other);
  const proto::XferBegin& b = x.begin;
  const proto::XferChunk& c = x.chunk;
  const proto::XferCommit& cm = x.commit;
  auto upload = [&] {
    ASSERT_EQ(must(peer_->request(b), "XFER_BEGIN").header.type, uint8_t(proto::MsgType::XferAck));
    ASSERT_EQ(as<proto::XferAck>(must(peer_->request(c), "XFER_CHUNK")).next_offset, other.size());
    ASSERT_EQ(must(peer_->request(cm), "XFER_COMMIT").header.type, uint8_t(proto::MsgType::Ack));
  };
  upload();
  EXPECT_EQ(model_hash(), crc);
  // the uploaded model runs; a new model transfer is refused meanwhile
  proto::RunStart start;
  start.run_id = 4;
  ASSERT_EQ(must(peer_->request(start), "RUN_START").header.type, uint8_t(proto::MsgType::Ack));
  const auto busy = must(peer_->request(b), "XFER_BEGIN while running");
  ASSERT_EQ(busy.header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(busy).status, uint8_t(proto::StatusCode::WrongState));
  EXPECT_EQ(model_hash(), crc);
  ASSERT_EQ(must(peer_->request(proto::RunStop{}), "RUN_STOP").header.type, uint8_t(proto::MsgType::Ack));
  // stopped: the transfer begins and the built-in model is in force until the commit
  ASSERT_EQ(must(peer_->request(b), "XFER_BEGIN").header.type, uint8_t(proto::MsgType::XferAck));
  EXPECT_EQ(model_hash(), builtin_hash);
  ASSERT_EQ(as<proto::XferAck>(must(peer_->request(c), "XFER_CHUNK")).next_offset, other.size());
  ASSERT_EQ(must(peer_->request(cm), "XFER_COMMIT").header.type, uint8_t(proto::MsgType::Ack));
  EXPECT_EQ(model_hash(), crc);
}

TEST_F(PosixFirmware, SilentLinkSendsActuatorsToTheSafeStateAndSaysSo) {
  proto::ParamSet wd;
  wd.id = uint16_t(fw::FwParamId::WatchdogMs);
  wd.count = 1;
  wd.values[0] = 150;
  ASSERT_EQ(must(peer_->request(wd), "PARAM_SET watchdog_ms").header.type, uint8_t(proto::MsgType::ParamValue));
  proto::TelemetryConfig off;
  off.mask = tf::kAll;
  off.decimation = 0;  // quiet, so our silence is the only thing going on
  ASSERT_TRUE(peer_->request(off).has_value());
  proto::RunStart start;
  start.run_id = 9;
  ASSERT_EQ(must(peer_->request(start), "RUN_START").header.type, uint8_t(proto::MsgType::Ack));
  usleep(600 * 1000);
  peer_->unsolicited.clear();
  const auto st = as<proto::Status>(must(peer_->request(proto::StatusGet{}), "STATUS_GET"));
  EXPECT_EQ(st.run_state, uint8_t(proto::RunState::Neutral));
  EXPECT_TRUE(st.watchdog & fw::watchdog_bits::kTripped);
  bool said_so = false;
  for (const auto& u : peer_->unsolicited)
    if (u.header.type == uint8_t(proto::MsgType::Log)) said_so = true;
  EXPECT_TRUE(said_so) << "no LOG when the link came back";
  proto::RunHold resume;
  resume.mode = uint8_t(proto::HoldMode::Resume);
  ASSERT_EQ(must(peer_->request(resume), "RUN_HOLD resume").header.type, uint8_t(proto::MsgType::Ack));
  const auto st2 = as<proto::Status>(must(peer_->request(proto::StatusGet{}), "STATUS_GET"));
  EXPECT_EQ(st2.run_state, uint8_t(proto::RunState::Running));
}

// The golden model file of PROTOCOL.md 9.4, built from the layout table
// alone, is taken as it is by the firmware it was made for, and a BEGIN
// the firmware refuses leaves the model in force.
TEST_F(PosixFirmware, TheGoldenModelFileUploadsAndRefusedBeginsChangeNothing) {
  std::ifstream in(NLSOFT_GOLDEN_MODEL);
  ASSERT_TRUE(in.good()) << NLSOFT_GOLDEN_MODEL;
  std::vector<uint8_t> file;
  uint32_t crc = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("crc32:", 0) == 0) crc = uint32_t(std::stoul(line.substr(6), nullptr, 16));
    if (line.rfind("file:", 0) != 0) continue;
    std::istringstream hex(line.substr(5));
    for (std::string b; hex >> b;) file.push_back(uint8_t(std::stoul(b, nullptr, 16)));
  }
  ASSERT_EQ(file.size(), 96u);
  auto info = [&] { return as<proto::InfoEx>(must(peer_->request(proto::InfoGet{}), "INFO_GET")); };
  const uint32_t builtin = info().info.model_hash;
  proto::XferBegin b;
  b.kind = uint8_t(proto::XferKind::Model);
  b.options = proto::xfer_options::kRestart;
  b.total_size = info().model_max + 1;
  EXPECT_EQ(as<proto::Nack>(must(peer_->request(b), "XFER_BEGIN too large")).status, uint8_t(proto::StatusCode::TooLarge));
  EXPECT_EQ(info().info.model_hash, builtin);

  ModelXfer x = model_xfer(file);
  x.begin.options = b.options;
  ASSERT_EQ(must(peer_->request(x.begin), "XFER_BEGIN").header.type, uint8_t(proto::MsgType::XferAck));
  ASSERT_EQ(as<proto::XferAck>(must(peer_->request(x.chunk), "XFER_CHUNK")).next_offset, file.size());
  ASSERT_EQ(must(peer_->request(x.commit), "XFER_COMMIT").header.type, uint8_t(proto::MsgType::Ack));
  EXPECT_EQ(info().info.model_hash, crc);
}

// Protocol 1.3 on the simulator's pty: an identification run of 2000 steps
// (2 simulated seconds of msd's PRBS) sends every step's u,
// the plant's output and no sensors (msd has none), loses no frame, keeps
// u inside msd's limits, and ends by itself.
TEST_F(PosixFirmware, AnIdentificationRunIsServedWholeAndEndsByItself) {
  ASSERT_EQ(must(peer_->request(watchdog_off()), "PARAM_SET watchdog_ms").header.type,
            uint8_t(proto::MsgType::ParamValue));
  const proto::IdentStart start = prbs_ident(9, 11, 2000);
  ASSERT_EQ(must(peer_->request(start), "IDENT_START").header.type, uint8_t(proto::MsgType::Ack));
  const std::vector<proto::IdentSample> s = ident_samples(*peer_, start.duration);
  ASSERT_EQ(s.size(), size_t(start.duration)) << "samples stopped";
  float lo = 1e9f, hi = -1e9f, ylo = 1e9f, yhi = -1e9f;
  for (size_t k = 0; k < s.size(); ++k) {
    ASSERT_EQ(s[k].step, k);
    ASSERT_EQ(s[k].m, 1);
    ASSERT_EQ(s[k].n, 1);
    ASSERT_EQ(s[k].w, 0);
    if (k > 0) {
      ASSERT_EQ(uint16_t(s[k].tseq - s[k - 1].tseq), 1u);
    }
    ASSERT_GE(s[k].u[0], -2000.0f);
    ASSERT_LE(s[k].u[0], 2000.0f);
    lo = std::min(lo, s[k].u[0]), hi = std::max(hi, s[k].u[0]);
    ylo = std::min(ylo, s[k].y[0]), yhi = std::max(yhi, s[k].y[0]);
  }
  EXPECT_FLOAT_EQ(hi - lo, 4000.0f);  // amplitude 1: the PRBS's two levels are msd's limits
  EXPECT_GT(yhi - ylo, 0.0f);   // and the mass moved
  const auto st = as<proto::Status>(must(peer_->request(proto::StatusGet{}), "STATUS_GET"));
  EXPECT_EQ(st.run_state, uint8_t(proto::RunState::Idle));
  EXPECT_EQ(st.step, start.duration);
}

namespace {

// The first `steps` samples of a PRBS identification run on a fresh
// simulator of hasel (18 noisy sensors) that idled `idle_ms` before it.
std::vector<proto::IdentSample> ident_after_idling(int idle_ms, uint32_t steps) {
  SimProcess sim({NLSOFT_FIRMWARE_SIM, "--platform", "hasel", "--fast"});
  EXPECT_FALSE(sim.path().empty()) << "the simulator printed no pty path";
  Peer peer(sim.path());
  EXPECT_TRUE(peer.ok());
  if (sim.path().empty() || !peer.ok()) return {};
  auto r = peer.request(watchdog_off());
  EXPECT_TRUE(r && r->header.type == uint8_t(proto::MsgType::ParamValue)) << "PARAM_SET watchdog_ms";
  // Idle, a fast simulator steps back to back, reading its sensors each step.
  std::this_thread::sleep_for(std::chrono::milliseconds(idle_ms));
  r = peer.request(prbs_ident(3, 5, steps));
  EXPECT_TRUE(r && r->header.type == uint8_t(proto::MsgType::Ack)) << "IDENT_START";
  return ident_samples(peer, steps);
}

}  // namespace

// The plant's noise starts over from the simulator's seed when a run
// begins: the same identification run gives the same data however long the
// simulator idled first (it reads its noisy sensors at every idle step).
TEST(PosixFirmwareNoise, TheSameIdentificationRunGivesTheSameDataAfterAnyIdleTime) {
  const auto a = ident_after_idling(0, 300), b = ident_after_idling(400, 300);
  ASSERT_EQ(a.size(), 300u);
  ASSERT_EQ(b.size(), 300u);
  for (size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].w, 18);
    ASSERT_EQ(a[k].step, b[k].step);
    for (int i = 0; i < a[k].m; ++i) ASSERT_EQ(a[k].u[i], b[k].u[i]) << "step " << k << " u" << i;
    for (int j = 0; j < a[k].n; ++j) ASSERT_EQ(a[k].y[j], b[k].y[j]) << "step " << k << " y" << j;
    for (int j = 0; j < a[k].w; ++j) ASSERT_EQ(a[k].l[j], b[k].l[j]) << "step " << k << " l" << j;
  }
}

namespace {

// SENSOR_STREAM with `on` answered: the reply's type and, for a NACK, its status and field.
std::optional<Received> sensor_stream(Peer& peer, uint8_t on) {
  proto::SensorStream s;
  s.on = on;
  return peer.request(s);
}

}  // namespace

// Protocol 1.6 (PROTOCOL.md 7 SENSOR_STREAM, SENSOR_SAMPLE; 9.6): a rig with
// sensors streams them on request. While on, each closed-loop TELEMETRY is
// preceded by the SENSOR_SAMPLE of its step, INFO's w wide; a value past 1
// is refused naming field 0; off, none comes. A rig without sensors (msd)
// has no capability and refuses the request `unsupported`.
TEST(PosixSensorStream, EachClosedLoopTelemetryFollowsItsStepsSensors) {
  SimProcess sim({NLSOFT_FIRMWARE_SIM, "--rig", "hasel", "--fast"});
  ASSERT_FALSE(sim.path().empty()) << "the simulator printed no pty path";
  Peer peer(sim.path());
  ASSERT_TRUE(peer.ok());
  auto info = peer.request(proto::InfoGet{});
  ASSERT_TRUE(info);
  const auto ex = as<proto::InfoEx>(*info);
  ASSERT_EQ(ex.info.w, 18);
  EXPECT_NE(ex.info.capabilities & proto::capability::kSensorStream, 0u);
  EXPECT_GE(ex.protocol_minor, 6);  // SENSOR_STREAM came with 1.6
  ASSERT_TRUE(peer.request(watchdog_off()));

  auto r = sensor_stream(peer, 2);
  ASSERT_TRUE(r && r->header.type == uint8_t(proto::MsgType::Nack));
  const auto nack = as<proto::Nack>(*r);
  EXPECT_EQ(nack.status, uint8_t(proto::StatusCode::OutOfRange));
  EXPECT_EQ(nack.field, 0);
  r = sensor_stream(peer, 1);
  ASSERT_TRUE(r && r->header.type == uint8_t(proto::MsgType::Ack));
  proto::TelemetryConfig tc;
  tc.mask = proto::telemetry_field::kAll;
  tc.decimation = 1;
  ASSERT_TRUE(peer.request(tc));
  proto::RunStart start;
  start.run_id = 9;
  r = peer.request(start);
  ASSERT_TRUE(r && r->header.type == uint8_t(proto::MsgType::Ack)) << "RUN_START";

  // 200 closed-loop steps, in arrival order.
  std::vector<Received> frames;
  size_t telemetry = 0;
  while (telemetry < 200) {
    auto t = peer.wait_for([](const Received& x) { return x.header.type == uint8_t(proto::MsgType::Telemetry); }, 2000);
    ASSERT_TRUE(t) << "TELEMETRY stopped after " << telemetry;
    for (auto& u : peer.unsolicited) frames.push_back(std::move(u));
    peer.unsolicited.clear();
    frames.push_back(std::move(*t));
    ++telemetry;
  }
  const uint8_t tt = uint8_t(proto::MsgType::Telemetry), st = uint8_t(proto::MsgType::SensorSample);
  size_t paired = 0;
  bool varies = false;
  std::optional<proto::SensorSample> first;
  for (size_t k = 0; k < frames.size(); ++k) {
    if (frames[k].header.type == st) {
      ASSERT_TRUE(k + 1 < frames.size() && frames[k + 1].header.type == tt) << "a SENSOR_SAMPLE not before a TELEMETRY";
      continue;
    }
    if (frames[k].header.type != tt) continue;
    ASSERT_GT(k, 0u);
    ASSERT_EQ(frames[k - 1].header.type, st) << "a TELEMETRY without its SENSOR_SAMPLE (frame " << k << ")";
    const auto s = as<proto::SensorSample>(frames[k - 1]);
    const auto t = as<proto::Telemetry>(frames[k]);
    ASSERT_EQ(s.step, t.step);
    ASSERT_EQ(s.w, 18);
    for (int i = 0; i < s.w; ++i) ASSERT_TRUE(std::isfinite(s.l[i]));
    if (!first) first = s;
    else varies = varies || std::memcmp(first->l, s.l, sizeof s.l) != 0;
    ++paired;
  }
  EXPECT_EQ(paired, 200u);
  EXPECT_TRUE(varies) << "the sensors never changed over 200 steps";

  // Off: the run goes on without them.
  r = sensor_stream(peer, 0);
  ASSERT_TRUE(r && r->header.type == uint8_t(proto::MsgType::Ack));
  peer.unsolicited.clear();
  size_t after = 0, stray = 0;
  while (after < 100) {
    auto t = peer.wait_for([](const Received& x) { return x.header.type == uint8_t(proto::MsgType::Telemetry); }, 2000);
    ASSERT_TRUE(t);
    ++after;
    for (const auto& u : peer.unsolicited) stray += u.header.type == st;
    peer.unsolicited.clear();
  }
  // What was queued before the ACK arrived before it.
  EXPECT_EQ(stray, 0u);

  SimProcess msd({NLSOFT_FIRMWARE_SIM, "--rig", "msd", "--fast"});
  ASSERT_FALSE(msd.path().empty());
  Peer msd_peer(msd.path());
  ASSERT_TRUE(msd_peer.ok());
  r = sensor_stream(msd_peer, 1);
  ASSERT_TRUE(r && r->header.type == uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(*r).status, uint8_t(proto::StatusCode::Unsupported));
}
