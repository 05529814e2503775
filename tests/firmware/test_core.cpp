// The firmware core's protocol services without a port: parameter list
// hashing and REF_SELECT validation (PROTOCOL.md 7, 9.1, 9.3).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "firmware/core/clock.hpp"
#include "firmware/core/compute_stats.hpp"
#include "firmware/core/param_service.hpp"
#include "firmware/core/reference_slot.hpp"
#include "shared/capacity.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
namespace proto = nlsoft::protocol;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

uint32_t hash_of(const char* rig) {
  Params<HostCapacity> params = test::shipped_params<HostCapacity>(rig);
  fw::FwSettings settings{};
  const host::Rig& r = test::shipped_rig_file(rig);
  return fw::ParamService<HostCapacity>(params, r.m(), r.n(), settings).hash();
}

TEST(ParamHash, IsTheCrcOfTheDescriptorPayloadsAndDiffersPerPlatform) {
  Params<HostCapacity> params = test::shipped_params<HostCapacity>("hasel");
  fw::FwSettings settings{};
  const fw::ParamService<HostCapacity> svc(params, 6, 3, settings);
  std::vector<uint8_t> all;
  for (uint16_t i = 0;; ++i) {
    proto::ParamDesc d;
    if (!svc.describe(i, d)) break;
    uint8_t payload[proto::kMaxPayload];
    size_t len = 0;
    ASSERT_EQ(proto::pack(d, payload, sizeof payload, len), proto::StatusCode::Ok);
    all.insert(all.end(), payload, payload + len);
  }
  EXPECT_EQ(svc.hash(), crc32(all.data(), all.size()));
  // diag(Q) has n elements (1, 3, 3) and diag(Lambda) m (1, 6, 2): every
  // platform's list, and so its hash, is its own.
  const std::set<uint32_t> hashes = {hash_of("msd"), hash_of("hasel"), hash_of("tendon")};
  EXPECT_EQ(hashes.size(), 3u);
}

using proto::RefId;

proto::RefSelect ref(RefId id) {
  proto::RefSelect r;
  r.ref_id = uint8_t(id);
  r.a = r.b = r.c = 1.0f;
  r.omega = 0.01f;
  r.lambda = 100.0f;
  r.scale = 1.0f;
  r.level_count = 3;
  r.levels[0] = 0.5f, r.levels[1] = 1.0f, r.levels[2] = 2.0f;
  return r;
}
struct Refusal {
  const char* what;
  proto::RefSelect msg;
  proto::StatusCode status;
  uint8_t field, element;
};

TEST(RefSelect, RefusalsNameTheFieldAndElement) {
  std::vector<Refusal> cases;
  auto add = [&](const char* what, proto::RefSelect m, proto::StatusCode s, uint8_t field, uint8_t element) {
    cases.push_back({what, m, s, field, element});
  };
  const uint8_t none = proto::kNoField;
  {
    auto m = ref(RefId::Infinity);
    m.ref_id = 7;
    add("ref_id 7", m, proto::StatusCode::UnknownId, 0, none);
  }
  {
    auto m = ref(RefId::Infinity);
    m.a = kNaN;
    add("infinity a=NaN", m, proto::StatusCode::NotFinite, 3, none);
  }
  {
    auto m = ref(RefId::Pringle);
    m.center[2] = kInf;
    add("pringle center[2]=Inf", m, proto::StatusCode::NotFinite, 6, 2);
  }
  {
    auto m = ref(RefId::Infinity);
    m.omega = kNaN;
    add("infinity omega=NaN", m, proto::StatusCode::NotFinite, 7, none);
  }
  {
    auto m = ref(RefId::Step);
    m.levels[1] = kNaN;
    add("step levels[1]=NaN", m, proto::StatusCode::NotFinite, 10, 1);
  }
  {
    auto m = ref(RefId::Step);
    m.level_count = 4;
    add("step level_count=4", m, proto::StatusCode::OutOfRange, 1, none);
  }
  {
    auto m = ref(RefId::Step);
    m.level_count = 0;
    add("step level_count=0", m, proto::StatusCode::OutOfRange, 1, none);
  }
  {
    auto m = ref(RefId::Diagonal);
    m.lambda = 0.0f;
    add("diagonal lambda=0", m, proto::StatusCode::OutOfRange, 8, none);
  }
  {
    auto m = ref(RefId::Pringle);
    m.c = 0.0f;
    add("pringle A with C=0", m, proto::StatusCode::Inconsistent, 5, none);
  }
  {
    auto m = ref(RefId::Swirl);
    m.scale = -kInf;
    add("swirl scale=-Inf", m, proto::StatusCode::NotFinite, 9, none);
  }
  for (const Refusal& c : cases) {
    RefParams out{};
    out.kind = RefKind::Hold;
    const fw::RefRefusal r = fw::check_ref_select(c.msg, out);
    EXPECT_EQ(r.status, c.status) << c.what;
    EXPECT_EQ(r.field, c.field) << c.what;
    EXPECT_EQ(r.element, c.element) << c.what;
    EXPECT_EQ(out.kind, RefKind::Hold) << c.what << ": a refused selection wrote its output";
  }
}

TEST(RefSelect, FieldsAReferenceDoesNotUseAreIgnoredAndCleared) {
  auto m = ref(RefId::Step);
  m.level_count = 1;
  m.levels[1] = kNaN;  // past level_count
  m.a = kNaN;
  m.omega = kInf;
  m.lambda = 0.0f;
  RefParams out{};
  const fw::RefRefusal r = fw::check_ref_select(m, out);
  ASSERT_EQ(r.status, proto::StatusCode::Ok);
  EXPECT_EQ(out.kind, RefKind::Step);
  EXPECT_EQ(out.level_count, 1);
  EXPECT_EQ(out.levels[0], 0.5f);
  EXPECT_EQ(out.levels[1], 0.0f);
  EXPECT_EQ(out.A, 0.0f);
  EXPECT_EQ(out.omega, 0.0f);
  EXPECT_EQ(reference_check(out), nullptr);
}

TEST(RefSelect, TableWithoutATableIsWrongStateAndLeavesTheReference) {
  float points[6] = {};
  fw::ReferenceSlot slot(points, 6);
  ASSERT_EQ(slot.select(ref(RefId::Hold)).status, proto::StatusCode::Ok);
  const fw::RefRefusal r = slot.select(ref(RefId::Table));
  EXPECT_EQ(r.status, proto::StatusCode::WrongState);
  EXPECT_EQ(r.field, 0);
  EXPECT_EQ(slot.id(), uint8_t(RefId::Hold));
  uint8_t obj[8 + 4 * 2] = {1, 1, 0, 0, 2, 0, 0, 0};
  ASSERT_EQ(slot.commit_table(obj, sizeof obj, 1), proto::StatusCode::Ok);
  EXPECT_EQ(slot.select(ref(RefId::Table)).status, proto::StatusCode::Ok);
  EXPECT_EQ(slot.id(), uint8_t(RefId::Table));
}

// A tick reading a little behind the last one (a counter extension racing
// its reload interrupt) must not count as a whole wrap: the watchdog would
// see 172 s of silence and trip.
TEST(Clock, AReadingBehindTheLastHoldsTheClockAndAWrapStillCounts) {
  fw::Clock c;
  c.start(1000, 1000);  // 1 tick = 1 ms
  c.update(1500);
  EXPECT_EQ(c.ms(), 500u);
  c.update(1400);  // behind: held
  EXPECT_EQ(c.ms(), 500u);
  c.update(1600);
  EXPECT_EQ(c.ms(), 600u);
  c.update(0x7FFFFF00u);  // read at least once per half wrap, then across the wrap
  c.update(0xFFFFFF00u);
  c.update(0x100u);
  EXPECT_EQ(c.total_ticks(), uint64_t(0xFFFFFF00u) - 1000u + 0x200u);
}

// The clock divides in 32 bits only (no 64-bit division on the MCU): its
// readings are still the 64-bit quotients of the ticks elapsed, at a board's
// clocks and at one above 429 MHz (Teensy 4.x), where ten ticks of a second
// no longer fit 32 bits.
TEST(Clock, MillisecondsAndMicrosecondsAreTheQuotientsOfTheTicksElapsed) {
  for (uint32_t rate : {7u, 1000u, 1000000u, 25000000u, 168000000u, 429496730u, 600000000u, 0xFFFFFFFFu}) {
    fw::Clock c;
    uint32_t t = 0xFFFF0000u;
    c.start(t, rate);
    uint64_t total = 0;
    uint32_t step = 1;
    for (int i = 0; i < 4000; ++i) {
      step = step * 1664525u + 1013904223u;
      const uint32_t delta = step % 0x7FFFFFFFu >> (i % 24);
      t += delta;
      total += delta;
      c.update(t);
      ASSERT_EQ(c.total_ticks(), total);
      ASSERT_EQ(c.ms(), uint32_t(total * 1000u / rate)) << rate << " after " << total;
      ASSERT_EQ(c.us(), uint32_t(total * 1000000u / rate)) << rate << " after " << total;
    }
  }
}

// STATUS's mean compute time is the floor of the 64-bit sum over the count,
// found without a 64-bit division, also once the sum has passed 2^32.
TEST(ComputeStats, TheMeanIsTheSumOverTheCountPastTwoToThe32) {
  fw::ComputeStats st;
  EXPECT_EQ(st.mean(), 0u);
  uint64_t sum = 0;
  uint32_t x = 7;
  for (int i = 0; i < 20000; ++i) {
    x = x * 1664525u + 1013904223u;
    const uint32_t ticks = i < 10000 ? x >> 12 : x | 0x80000000u;
    st.add(ticks);
    sum += ticks;
    ASSERT_EQ(st.mean(), uint32_t(sum / st.count)) << i;
  }
  EXPECT_GT(sum, uint64_t(1) << 44);
}

}  // namespace
