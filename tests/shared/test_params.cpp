// The parameter table: every refused write names its reason and changes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "shared/params.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
using Cap = HostCapacity;

class ParamTable : public ::testing::Test {
 protected:
  void SetUp() override { P = test::shipped_params<Cap>("hasel"); }
  bool unchanged() const {
    for (int i = 0; i < int(ParamId::Count); ++i) {
      float a[8], b[8];
      const int c = get_param(P, ParamId(i), m, n, a);
      get_param(before, ParamId(i), m, n, b);
      if (std::memcmp(a, b, sizeof(float) * size_t(c)) != 0) return false;
    }
    return true;
  }
  void snapshot() { before = P; }
  Params<Cap> P, before;
  const int m = 6, n = 3;
};

TEST_F(ParamTable, EveryIdHasOneDescriptorWithSaneBounds) {
  for (int i = 0; i < int(ParamId::Count); ++i) {
    const ParamDesc& d = kParamTable[i];
    EXPECT_EQ(int(d.id), i);
    EXPECT_LE(d.min, d.max) << d.name;
    EXPECT_EQ(find_param(d.name), &d);
    EXPECT_GT(std::strlen(d.meaning), 5u) << d.name;
  }
  EXPECT_EQ(find_param("nope"), nullptr);
}

TEST_F(ParamTable, VectorWriteIsAppliedAndEchoed) {
  const float q[3] = {1.0f, 2.0f, 3.0f};
  EXPECT_EQ(set_param(P, ParamId::Q, q, 3, m, n).status, Status::Ok);
  float out[8];
  ASSERT_EQ(get_param(P, ParamId::Q, m, n, out), 3);
  EXPECT_EQ(out[1], 2.0f);
}

TEST_F(ParamTable, RefusesWithReasonAndIndexAndChangesNothing) {
  snapshot();
  const float q_nan[3] = {1.0f, 2.0f, std::nanf("")};
  ParamResult r = set_param(P, ParamId::Q, q_nan, 3, m, n);
  EXPECT_EQ(r.status, Status::NotFinite);
  EXPECT_EQ(r.index, 2);
  const float q_neg[3] = {1.0f, -2.0f, 3.0f};
  r = set_param(P, ParamId::Q, q_neg, 3, m, n);
  EXPECT_EQ(r.status, Status::OutOfRange);
  EXPECT_EQ(r.index, 1);
  EXPECT_EQ(set_param(P, ParamId::Q, q_neg, 2, m, n).status, Status::WrongSize);
  const float frac[1] = {2.5f};
  EXPECT_EQ(set_param(P, ParamId::N, frac, 1, m, n).status, Status::OutOfRange);
  const float big[1] = {200.0f};
  EXPECT_EQ(set_param(P, ParamId::N, big, 1, m, n).status, Status::TooLarge);  // > Cap::N
  const float one[1] = {1.0f};
  EXPECT_EQ(set_param(P, ParamId::N, one, 1, m, n).status, Status::Ok);  // N = 1 >= Nc = 1
  snapshot();
  const float two[1] = {2.0f};
  EXPECT_EQ(set_param(P, ParamId::Nc, two, 1, m, n).status, Status::Inconsistent);  // Nc > N
  float lo[6] = {0, 0, 0, 2, 0, 0};  // u_min[3] > u_max[3] = 1
  r = set_param(P, ParamId::UMin, lo, 6, m, n);
  EXPECT_EQ(r.status, Status::Inconsistent);
  EXPECT_EQ(r.index, 3);
  const float mode[1] = {2.0f};
  EXPECT_EQ(set_param(P, ParamId::Mode, mode, 1, m, n).status, Status::OutOfRange);
  EXPECT_EQ(set_param(P, ParamId(200), one, 1, m, n).status, Status::UnknownId);
  EXPECT_TRUE(unchanged());
}

