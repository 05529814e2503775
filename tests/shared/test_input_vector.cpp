// The roll of Algorithm 1, element by element.
#include <gtest/gtest.h>

#include "shared/input_vector.hpp"

using namespace nlsoft;

TEST(Roll, ShiftsWithinBoundsOnly) {
  float q[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  roll(q, 0, 6, 2);  // the paper's figure: push/pop bsize elements in [start, end)
  const float want[8] = {0, 1, 0, 1, 2, 3, 6, 7};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(q[i], want[i]) << i;
}

TEST(Algorithm1, BuildsNewestFirstQueuesThenSensors) {
  const InputLayout L{2, 3, 2, 2, 2};  // m=2, n=3, w=2, nd=dd=2 -> p = 4 + 6 + 2
  ASSERT_EQ(L.p(), 12);
  float x[12] = {};
  const float u1[2] = {1, 2}, u2[2] = {3, 4};
  const float y1[3] = {10, 11, 12}, y2[3] = {20, 21, 22};
  const float l[2] = {7, 8};
  push_input(x, L, u1);
  push_output(x, L, y1);
  push_input(x, L, u2);
  push_output(x, L, y2);
  set_sensors(x, L, l);
  const float want[12] = {3, 4, 1, 2, 20, 21, 22, 10, 11, 12, 7, 8};
  for (int i = 0; i < 12; ++i) EXPECT_EQ(x[i], want[i]) << i;
  // a third push drops the oldest entries and leaves the other queue alone
  const float u3[2] = {5, 6};
  push_input(x, L, u3);
  const float want3[12] = {5, 6, 3, 4, 20, 21, 22, 10, 11, 12, 7, 8};
  for (int i = 0; i < 12; ++i) EXPECT_EQ(x[i], want3[i]) << i;
}
