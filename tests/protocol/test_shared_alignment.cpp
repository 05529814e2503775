// The protocol's enums and REF_SELECT layout are numbered to match shared/,
// so the firmware can pass values through with a cast or a memcpy. These
// tests fail the moment either side renumbers.

#include <gtest/gtest.h>

#include <cstring>

#include "protocol/messages.hpp"
#include "protocol/status.hpp"
#include "shared/params.hpp"
#include "shared/platform_id.hpp"
#include "shared/reference.hpp"
#include "shared/status.hpp"

namespace np = nlsoft::protocol;

namespace {

TEST(SharedAlignment, StatusCodesZeroToEightEqualSharedStatus) {
  using S = nlsoft::Status;
  using W = np::StatusCode;
  const std::pair<S, W> pairs[] = {
      {S::Ok, W::Ok},
      {S::OutOfRange, W::OutOfRange},
      {S::NotFinite, W::NotFinite},
      {S::WrongSize, W::WrongSize},
      {S::UnknownId, W::UnknownId},
      {S::Inconsistent, W::Inconsistent},
      {S::TooLarge, W::TooLarge},
      {S::BadFormat, W::BadFormat},
      {S::BadChecksum, W::BadChecksum},
  };
  for (const auto& [s, w] : pairs) EXPECT_EQ(static_cast<int>(s), static_cast<int>(w));
}

TEST(SharedAlignment, PlatformParamTypeAndReferenceNumbersMatch) {
  EXPECT_EQ(int(np::Platform::Msd), int(nlsoft::PlatformId::Msd));
  EXPECT_EQ(int(np::Platform::Hasel), int(nlsoft::PlatformId::Hasel));
  EXPECT_EQ(int(np::Platform::Tendon), int(nlsoft::PlatformId::Tendon));
  EXPECT_EQ(int(np::ParamType::F32), int(nlsoft::ParamType::F32));
  EXPECT_EQ(int(np::ParamType::U8), int(nlsoft::ParamType::U8));
  EXPECT_EQ(int(np::ParamType::Enum), int(nlsoft::ParamType::Enum));
  EXPECT_EQ(int(np::RefId::Infinity), int(nlsoft::RefKind::Infinity));
  EXPECT_EQ(int(np::RefId::Pringle), int(nlsoft::RefKind::Pringle));
  EXPECT_EQ(int(np::RefId::Diagonal), int(nlsoft::RefKind::Diagonal));
  EXPECT_EQ(int(np::RefId::Swirl), int(nlsoft::RefKind::Swirl));
  EXPECT_EQ(int(np::RefId::Step), int(nlsoft::RefKind::Step));
  EXPECT_EQ(int(np::RefId::Table), int(nlsoft::RefKind::Table));
  EXPECT_EQ(int(np::RefId::Hold), int(nlsoft::RefKind::Hold));
}

TEST(SharedAlignment, RefSelectPayloadIsByteIdenticalToSharedRefParams) {
  nlsoft::RefParams p{};
  p.kind = nlsoft::RefKind::Step;
  p.level_count = 3;
  p.hold = 2000;
  p.A = 1.5f;
  p.B = 2.5f;
  p.C = 3.5f;
  p.c[0] = 0.1f;
  p.c[1] = 0.2f;
  p.c[2] = 0.3f;
  p.omega = 0.05f;
  p.lambda = 400.0f;
  p.scale = 1.25f;
  p.levels[0] = 0.5f;
  p.levels[1] = 1.0f;
  p.levels[2] = 2.0f;

  np::RefSelect r;
  r.ref_id = static_cast<uint8_t>(np::RefId::Step);
  r.level_count = 3;
  r.hold = 2000;
  r.a = 1.5f;
  r.b = 2.5f;
  r.c = 3.5f;
  r.center[0] = 0.1f;
  r.center[1] = 0.2f;
  r.center[2] = 0.3f;
  r.omega = 0.05f;
  r.lambda = 400.0f;
  r.scale = 1.25f;
  r.levels[0] = 0.5f;
  r.levels[1] = 1.0f;
  r.levels[2] = 2.0f;

  uint8_t payload[np::kMaxPayload];
  size_t len = 0;
  ASSERT_EQ(np::pack(r, payload, sizeof payload, len), np::StatusCode::Ok);
  ASSERT_EQ(len, sizeof p);
  EXPECT_EQ(std::memcmp(payload, &p, sizeof p), 0);  // host is little-endian, like the MCU
}

}  // namespace
