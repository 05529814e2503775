#pragma once
// fmod for the references' phases (sincos.hpp, reference.hpp), exact as
// std::fmod is, without libm's: newlib's fmodf, with the errno it sets and
// the reentrancy block that comes with it, is ~550 B of an image's flash,
// for an operation that is a handful of exact subtractions.
//
// |x| mod y by binary long division on the floats themselves: d runs down
// from the largest y 2^j <= |x| to y, and r -= d whenever r >= d. Every d
// is exact (a power-of-two scaling of y), and r < 2d holds at each step,
// so r - d is exact (Sterbenz: d <= r <= 2d): the result is the exact
// remainder, which is representable, the same bits as std::fmod. At most
// log2(|x| / y) + 1 turns: 24 for a reference's step count (k < 2^24).
namespace nlsoft {

// x finite (else NaN), y finite and > 0; the result has x's sign, as fmod's.
inline float fmod_exact(float x, float y) {
  if (!(x - x == 0.0f)) return x - x;
  const float a = x < 0.0f ? -x : x;
  if (!(a >= y)) return x;
  float d = y;
  while (d <= 0.5f * a) d *= 2.0f;
  float r = a;
  for (; d >= y; d *= 0.5f)
    if (r >= d) r -= d;
  return x < 0.0f ? -r : r;
}

}  // namespace nlsoft
