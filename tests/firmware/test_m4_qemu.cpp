// The Cortex-M4F images in QEMU (-icount shift=0), driven over the UART's
// pty as the console drives a board: the MPS2 AN386 images on -M mps2-an386,
// the STM32F4 Nucleo-64 images on -M netduinoplus2 (an STM32F405: USART2,
// no RCC, so the image's bounded clock waits time out and it reports QEMU's
// fixed 168 MHz). Skipped only where qemu-system-arm or the cross-built
// images are absent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "firmware/core/param_service.hpp"
#include "peer.hpp"
#include "qemu_process.hpp"
#include "shared/excitation.hpp"
#include "shared/model_file.hpp"
#include "shared/params.hpp"
#include "shared/platform_id.hpp"

using namespace nlsoft;
using namespace nlsoft::test;
namespace tf = proto::telemetry_field;

namespace {

class M4Image : public ::testing::Test {
 protected:
  void boot(const std::string& elf, const std::string& board = "mps2-an386") {
    if (!qemu_arm_available()) GTEST_SKIP() << "qemu-system-arm is not installed: the M4 image test needs it";
    if (!std::ifstream(elf).good())
      GTEST_SKIP() << elf << " was not built (arm-none-eabi-g++ missing when configuring)";
    qemu_ = std::make_unique<QemuProcess>(elf, board);
    ASSERT_FALSE(qemu_->path().empty()) << "QEMU reported no pty:\n" << qemu_->log();
    peer_ = std::make_unique<Peer>(qemu_->path());
    ASSERT_TRUE(peer_->ok());
  }
  // Bytes the image sends before the pty is opened are lost and the guest
  // may still be booting: ask until it answers.
  proto::Info handshake() {
    for (int attempt = 0; attempt < 40; ++attempt)
      if (auto r = peer_->request(proto::InfoGet{}, 250)) {
        ex_ = as<proto::InfoEx>(*r);
        return ex_.info;
      }
    ADD_FAILURE() << "no INFO from the image after 10 s";
    return {};
  }
  proto::InfoEx ex_;
  Received must(std::optional<Received> r, const char* what) {
    EXPECT_TRUE(r.has_value()) << "no reply to " << what;
    return r.value_or(Received{});
  }
  std::unique_ptr<QemuProcess> qemu_;
  std::unique_ptr<Peer> peer_;

  // The session the console holds with a HIL image: handshake, a parameter
  // round trip and a refused one, a run with telemetry, STATUS.
  void hasel_hil_session(const char* firmware, uint32_t tick_rate_hz) {
    const proto::Info info = handshake();
    EXPECT_EQ(info.platform, uint8_t(PlatformId::Hasel));
    EXPECT_EQ(info.m, 6);
    EXPECT_EQ(info.n, 3);
    EXPECT_EQ(info.w, 18);
    EXPECT_EQ(info.loop_rate_hz, 130u);
    EXPECT_STREQ(info.firmware, firmware);
    EXPECT_TRUE(info.capabilities & proto::capability::kYTrue);
    ASSERT_NE(info.model_hash, 0u) << "the image has no model: app/models/hasel.nlsm was missing at build time";

    auto v = as<proto::ParamValue>(must(peer_->request(param_set(ParamId::Q, {2e6f, 1e6f, 3e6f})), "PARAM_SET Q"));
    EXPECT_FLOAT_EQ(v.f32(2), 3e6f);
    proto::ParamGet g;
    g.id = uint16_t(ParamId::Q);
    v = as<proto::ParamValue>(must(peer_->request(g), "PARAM_GET Q"));
    EXPECT_FLOAT_EQ(v.f32(0), 2e6f);
    EXPECT_FLOAT_EQ(v.f32(1), 1e6f);
    EXPECT_FLOAT_EQ(v.f32(2), 3e6f);
    const auto nack = must(peer_->request(param_set(ParamId::Q, {std::nanf(""), 1.0f, 1.0f})), "PARAM_SET NaN");
    EXPECT_EQ(nack.header.type, uint8_t(proto::MsgType::Nack));

    proto::TelemetryConfig tc;
    tc.mask = tf::kStep | tf::kYRef | tf::kYTrue | tf::kU | tf::kSolver;
    tc.decimation = 1;
    ASSERT_EQ(must(peer_->request(tc), "TELEMETRY_CONFIG").header.type, uint8_t(proto::MsgType::Ack));
    proto::RunStart start;
    start.run_id = 42;
    ASSERT_EQ(must(peer_->request(start), "RUN_START").header.type, uint8_t(proto::MsgType::Ack));

    std::vector<proto::Telemetry> t;
    while (t.size() < 20) {
      auto r = peer_->wait_for([](const Received& x) { return x.header.type == uint8_t(proto::MsgType::Telemetry); },
                               3000);
      ASSERT_TRUE(r.has_value()) << "telemetry stopped after " << t.size() << " frames";
      t.push_back(as<proto::Telemetry>(*r));
    }
    peer_->unsolicited.clear();
    for (size_t i = 0; i < t.size(); ++i) {
      EXPECT_GT(t[i].compute_ticks, 0u) << "step " << t[i].step;
      EXPECT_GE(t[i].iterations, 1);
      for (int a = 0; a < 6; ++a) {
        EXPECT_GE(t[i].u[a], 0.0f);
        EXPECT_LE(t[i].u[a], 1.0f);
      }
      if (i > 0) {
        EXPECT_EQ(t[i].step, t[i - 1].step + 1);
      }
    }
    const auto st = as<proto::Status>(must(peer_->request(proto::StatusGet{}), "STATUS_GET"));
    EXPECT_EQ(st.tick_rate_hz, tick_rate_hz);
    EXPECT_EQ(st.run_id, 42u);
    EXPECT_GT(st.compute_min, 0u);
    EXPECT_GE(st.compute_max, st.compute_mean);
    EXPECT_GE(st.compute_mean, st.compute_min);
    EXPECT_EQ(st.crc_errors, 0u);
    ASSERT_EQ(must(peer_->request(proto::RunStop{}), "RUN_STOP").header.type, uint8_t(proto::MsgType::Ack));
  }
};

}  // namespace

TEST_F(M4Image, HaselHilHandshakesRoundTripsAParameterAndRuns) {
  boot(NLSOFT_M4_IMAGE_DIR "/nlsoft-m4-hasel-hil.elf");
  if (IsSkipped() || HasFatalFailure()) return;
  hasel_hil_session("nlsoft-an386-hil", 25000000u);
}

TEST_F(M4Image, Stm32f4HaselHilHandshakesRoundTripsAParameterAndRunsInNetduinoplus2) {
  boot(NLSOFT_STM32F4_IMAGE_DIR "/nlsoft-stm32f4-hasel-hil.elf", "stm32f4");
  if (IsSkipped() || HasFatalFailure()) return;
  hasel_hil_session(NLSOFT_STM32F4_FIRMWARE "-hil", 168000000u);
}

TEST_F(M4Image, Stm32f4RigImageBootsWithItsPwmAndAdcAndServesTheLink) {
  boot(NLSOFT_STM32F4_IMAGE_DIR "/nlsoft-stm32f4-tendon.elf", "stm32f4");
  if (IsSkipped() || HasFatalFailure()) return;
  const proto::Info info = handshake();
  EXPECT_EQ(info.platform, uint8_t(PlatformId::Tendon));
  EXPECT_STREQ(info.firmware, NLSOFT_STM32F4_FIRMWARE);
  EXPECT_FALSE(info.capabilities & proto::capability::kYTrue);
  proto::Ping ping;
  ping.nonce = 0xF446;
  EXPECT_EQ(as<proto::Pong>(must(peer_->request(ping), "PING")).nonce, 0xF446u);
}

// The stm32f4 images carry the settings store over the part's flash
// (ports/stm32f4/flash.hpp), but netduinoplus2 models no flash interface
// (0x40023C00 reads 0 and ignores writes, the flash is ROM): the image
// finds none at boot and claims no SETTINGS, and a SETTINGS request is
// refused as unsupported rather than failing in the flash. The driver
// itself is tested against a model of the interface (test_stm32f4_flash.cpp).
TEST_F(M4Image, Stm32f4ImageClaimsNoSettingsWhereTheFlashInterfaceDoesNotAnswer) {
  boot(NLSOFT_STM32F4_IMAGE_DIR "/nlsoft-stm32f4-tendon.elf", "stm32f4");
  if (IsSkipped() || HasFatalFailure()) return;
  const proto::Info info = handshake();
  EXPECT_FALSE(info.capabilities & proto::capability::kSettings);
  proto::Settings save;
  save.action = uint8_t(proto::SettingsAction::Save);
  const Received r = must(peer_->request(save), "SETTINGS save");
  ASSERT_EQ(r.header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(r).status, uint8_t(proto::StatusCode::Unsupported));
}

// hasel's board image reads six LIS3MDL on SPI2; netduinoplus2 has the SPI
// controller but no chip on it, so each reads back undriven: the image
// reports every chip absent (DEVICE_STATUS, at its chip select) and every
// magnetometer channel invalid (SENSOR_HEALTH after each sample, age_ms
// 65535: no valid chip sample), drops none of its boot LOGs, and serves
// the link and runs the controller all the same: a missing chip is reported,
// not fatal.
TEST_F(M4Image, Stm32f4HaselImageReportsItsSixAbsentChipsAndRunsInNetduinoplus2) {
  boot(NLSOFT_STM32F4_IMAGE_DIR "/nlsoft-stm32f4-hasel.elf", "stm32f4");
  if (IsSkipped() || HasFatalFailure()) return;
  const proto::Info info = handshake();
  EXPECT_EQ(info.platform, uint8_t(PlatformId::Hasel));
  EXPECT_STREQ(info.firmware, NLSOFT_STM32F4_FIRMWARE);
  ASSERT_TRUE(info.capabilities & proto::capability::kDevices);
  for (uint8_t d = 0; d < 6; ++d) {
    SCOPED_TRACE(int(d));
    proto::DeviceGet g;
    g.index = d;
    const auto s = as<proto::DeviceStatus>(must(peer_->request(g), "DEVICE_GET"));
    EXPECT_EQ(s.count, 6);
    EXPECT_EQ(s.state, uint8_t(proto::DeviceState::Absent));
    EXPECT_EQ(s.address, d);  // chip select d of the board's list (PB12 PA8 PA9 PA10 PB4 PB5)
    EXPECT_EQ(s.age_ms, proto::kNoSample);
    EXPECT_GE(s.faults, 1u);
    EXPECT_EQ(std::string(s.name), "mag" + std::to_string(d + 1));
  }
  proto::DeviceGet past;
  past.index = 6;
  EXPECT_EQ(must(peer_->request(past), "DEVICE_GET 6").header.type, uint8_t(proto::MsgType::Nack));
  // Its six boot LOGs (one per absent chip) are more than the 512-byte TX
  // queue holds at once: they wait for room, none is dropped (PROTOCOL.md 7,
  // DEVICE_STATUS). Those sent before the pty was opened are lost to QEMU,
  // not to the firmware, which counts only its own drops.
  EXPECT_EQ(as<proto::Status>(must(peer_->request(proto::StatusGet{}), "STATUS_GET")).tx_dropped, 0u)
      << "a boot LOG dropped";

  ASSERT_NE(info.model_hash, 0u) << "the image has no model: app/models/hasel.nlsm was missing at build time";
  proto::TelemetryConfig tc;
  tc.mask = tf::kStep | tf::kU;
  tc.decimation = 1;
  ASSERT_EQ(must(peer_->request(tc), "TELEMETRY_CONFIG").header.type, uint8_t(proto::MsgType::Ack));
  proto::RunStart start;
  start.run_id = 7;
  ASSERT_EQ(must(peer_->request(start), "RUN_START").header.type, uint8_t(proto::MsgType::Ack));
  for (int i = 0; i < 10; ++i) {
    auto r = peer_->wait_for([](const Received& x) { return x.header.type == uint8_t(proto::MsgType::SensorHealth); },
                             3000);
    ASSERT_TRUE(r.has_value()) << "no SENSOR_HEALTH after " << i;
    EXPECT_EQ(as<proto::SensorHealth>(*r).invalid, (1u << 18) - 1u) << "every magnetometer channel invalid";
    EXPECT_EQ(as<proto::SensorHealth>(*r).age_ms, 0xFFFFu) << "no valid chip sample";
  }
  ASSERT_EQ(must(peer_->request(proto::RunStop{}), "RUN_STOP").header.type, uint8_t(proto::MsgType::Ack));
}

TEST_F(M4Image, RealBoardImageServesTheLinkWithoutAPlant) {
  boot(NLSOFT_M4_IMAGE_DIR "/nlsoft-m4-msd.elf");
  if (IsSkipped() || HasFatalFailure()) return;
  const proto::Info info = handshake();
  EXPECT_EQ(info.platform, uint8_t(PlatformId::Msd));
  EXPECT_EQ(info.m, 1);
  EXPECT_STREQ(info.firmware, "nlsoft-an386");
  EXPECT_FALSE(info.capabilities & proto::capability::kYTrue);
  proto::Ping ping;
  ping.nonce = 0xBEEF;
  EXPECT_EQ(as<proto::Pong>(must(peer_->request(ping), "PING")).nonce, 0xBEEFu);
}

// Protocol 1.2 on the hasel image: RIG_INFO lists the one shape its kernel
// is built for, and the image itself refuses a model of another shape at
// XFER_BEGIN by its size (Dense 36->4->5->3), changing nothing.
TEST_F(M4Image, HaselImageListsItsOneShapeAndRefusesAnotherAtBegin) {
  boot(NLSOFT_M4_IMAGE_DIR "/nlsoft-m4-hasel-hil.elf");
  if (IsSkipped() || HasFatalFailure()) return;
  const proto::Info info = handshake();
  ASSERT_TRUE(info.capabilities & proto::capability::kRig);
  const auto rig = as<proto::RigInfo>(must(peer_->request(proto::RigGet{}), "RIG_GET"));
  EXPECT_STREQ(rig.rig_name, "hasel");
  EXPECT_EQ(rig.accept, proto::shape_accept::kList);
  EXPECT_EQ(std::vector<uint8_t>(rig.shapes, rig.shapes + rig.shapes_size),
            (std::vector<uint8_t>{3, 1, 5, 0, 1, 5, 0, 1, 3, 0}));
  proto::XferBegin b;
  b.kind = uint8_t(proto::XferKind::Model);
  b.total_size = uint32_t(model_file_size(3, 2 * 36 + 2 * 3 + (36 * 4 + 4) + (4 * 5 + 5) + (5 * 3 + 3)));
  b.crc32 = 1;
  const auto n = must(peer_->request(b), "XFER_BEGIN");
  ASSERT_EQ(n.header.type, uint8_t(proto::MsgType::Nack));
  EXPECT_EQ(as<proto::Nack>(n).status, uint8_t(proto::StatusCode::Unsupported));
  EXPECT_EQ(as<proto::Nack>(n).field, 2);
  const auto again = as<proto::InfoEx>(must(peer_->request(proto::InfoGet{}), "INFO_GET"));
  EXPECT_EQ(again.info.model_hash, info.model_hash);
}

// The excitation the Cortex-M4F computes is the host's, bit for bit: an
// identification run of each signal with uniform levels on the hasel image
// sends the u of shared/excitation.hpp run on the host with the same fields
// and the image's own limits.
TEST_F(M4Image, AnIdentificationRunsInputsAreTheHostsBitForBit) {
  boot(NLSOFT_M4_IMAGE_DIR "/nlsoft-m4-hasel-hil.elf");
  if (IsSkipped() || HasFatalFailure()) return;
  const proto::Info info = handshake();
  ASSERT_TRUE(info.capabilities & proto::capability::kIdentMixed);
  float u_min[kRigMaxM], u_max[kRigMaxM];
  for (ParamId id : {ParamId::UMin, ParamId::UMax}) {
    proto::ParamGet g;
    g.id = uint16_t(id);
    const auto v = as<proto::ParamValue>(must(peer_->request(g), "PARAM_GET"));
    for (uint8_t i = 0; i < info.m; ++i) (id == ParamId::UMin ? u_min : u_max)[i] = v.f32(i);
  }
  const float neutral[kRigMaxM] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};  // rigs/hasel.toml
  const struct {
    proto::IdentSignal signal;
    uint8_t options;
  } runs[] = {{proto::IdentSignal::Steps, 0},
              {proto::IdentSignal::Prbs, 0},
              {proto::IdentSignal::Aprbs, 0},
              {proto::IdentSignal::Aprbs, proto::ident_options::kMixed}};
  uint32_t run_id = 77;
  for (const auto& run : runs) {
    SCOPED_TRACE(testing::Message() << "signal " << int(run.signal) << " options " << int(run.options));
    proto::IdentStart start;
    start.run_id = run_id++;
    start.signal = uint8_t(run.signal);
    start.options = run.options;
    start.decimation = 1;
    start.seed = 12345;
    start.amplitude = 0.8f;
    start.band_lo = 0.5f;
    start.band_hi = 20.0f;
    start.duration = 150;
    ASSERT_EQ(must(peer_->request(start), "IDENT_START").header.type, uint8_t(proto::MsgType::Ack));
    std::vector<proto::IdentSample> got;
    const auto is_sample = [](const Received& x) { return x.header.type == uint8_t(proto::MsgType::IdentSample); };
    while (got.size() < start.duration) {
      // STATUS now and then feeds the link watchdog, which trips an
      // identification run too; the samples meanwhile are kept in order.
      if (got.size() % 40 == 39) {
        peer_->unsolicited.clear();
        must(peer_->request(proto::StatusGet{}), "STATUS_GET");
        for (const Received& x : peer_->unsolicited)
          if (is_sample(x)) got.push_back(as<proto::IdentSample>(x));
        peer_->unsolicited.clear();
        continue;
      }
      auto r = peer_->wait_for(is_sample, 3000);
      ASSERT_TRUE(r.has_value()) << "IDENT_SAMPLE stopped after " << got.size();
      got.push_back(as<proto::IdentSample>(*r));
    }
    got.resize(start.duration);
    ExcitationSpec spec;
    spec.signal = ExcitationSignal(start.signal);
    spec.mixed = run.options != 0;
    spec.seed = start.seed, spec.amplitude = start.amplitude, spec.band_lo = start.band_lo;
    spec.band_hi = start.band_hi, spec.duration = start.duration;
    Excitation host;
    ASSERT_EQ(host.configure(spec, float(info.loop_rate_hz), u_min, u_max, neutral, info.m).status, Status::Ok);
    int moves = 0;
    for (size_t k = 0; k < got.size(); ++k) {
      float u[kRigMaxM];
      host.next(u);
      ASSERT_EQ(got[k].step, k);
      for (int i = 0; i < info.m; ++i)
        ASSERT_EQ(std::memcmp(&u[i], &got[k].u[i], sizeof(float)), 0)
            << "step " << k << " input " << i << ": host " << std::hexfloat << u[i] << ", image " << got[k].u[i];
      moves += k > 0 && got[k].u[0] != got[k - 1].u[0];
    }
    EXPECT_GT(moves, 0) << "the run moved its inputs";
    // The run has ended by itself; wait for the image to say so.
    peer_->wait_for([](const Received& x) { return x.header.type == uint8_t(proto::MsgType::Log); }, 2000);
  }
}
