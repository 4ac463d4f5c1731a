#include "quack/math/trig.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

// Method. Sine and cosine: the argument is reduced to r in [-pi/4, pi/4] and a quadrant
// (Payne and Hanek, "Radian reduction for trigonometric functions", SIGNUM Newsletter 18(1),
// 1983: multiply the float's integer mantissa by the bits of 2/pi that matter, in integer
// arithmetic, so the reduction is exact for every float); then Taylor polynomials of sin and
// cos in double, whose truncation error on [-pi/4, pi/4] is below 2^-53. Arctangent: the
// classic reductions atan(x) = pi/2 - atan(1/x) and atan(x) = pi/6 + atan((sqrt(3) x - 1) /
// (sqrt(3) + x)) (as in Cody and Waite, "Software Manual for the Elementary Functions",
// 1980, and Cephes' atan) bring the argument below tan(pi/12), where the Taylor series
// converges to double precision in 14 terms. Learned from Box2D v3's b2ComputeCosSin (own
// polynomials instead of the C library, for cross-platform determinism) and musl's
// __rem_pio2_large; the code is Quack's own.
//
// Everything is evaluated in double and rounded to float once at the end: double add,
// multiply and divide are correctly rounded on every IEEE-754 platform, and this file is
// compiled with -ffp-contract=off (cmake/QuackTarget.cmake), so no fused multiply-add
// changes a bit. No long double, no C library maths except the exact fabs/copysign.

namespace quack {
namespace {

constexpr double kPi = 0x1.921fb54442d18p+1;
constexpr double kPiOver2 = 0x1.921fb54442d18p+0;
constexpr double kPiOver4 = 0x1.921fb54442d18p-1;
constexpr double kPiOver6 = 0x1.0c152382d7366p-1;
constexpr double kSqrt3 = 0x1.bb67ae8584caap+0;
constexpr double kTanPiOver12 = 0x1.126145e9ecd56p-2;  // 2 - sqrt(3)

// 2/pi in binary, 32 bits a word: 0.A2F9836E 4E441529 ... (computed with mpmath at 400 bits).
constexpr std::uint32_t kTwoOverPi[] = {0xA2F9836E, 0x4E441529, 0xFC2757D1, 0xF534DDC0,
                                        0xDB629599, 0x3C439041, 0xFE5163AB};

struct Reduced {
  double r;           // the argument minus quadrant * pi/2, in [-pi/4, pi/4]
  unsigned quadrant;  // modulo 4
};

// x (finite, |x| >= pi/4) as quadrant * pi/2 + r.
Reduced reduce(float x) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);  // not std::bit_cast: emscripten 3.1.6's libc++ lacks it
  const bool negative = (bits >> 31) != 0;
  const int biased = static_cast<int>((bits >> 23) & 0xFF);
  // |x| = m 2^e with m an integer below 2^24 (|x| >= pi/4 is normal).
  const std::uint64_t m = (bits & 0x7FFFFF) | 0x800000;
  const int e = biased - 150;
  // x 2/pi = m 2^e sum_j w_j 2^(-32 (j+1)). Word j's term is a multiple of 4 (a whole number
  // of turns) when e - 32 j - 32 >= 2: start at the first word that is not.
  int first = 0;
  while (e - 32 * first - 32 >= 2)
    ++first;
  // P = m (w_first 2^96 + w_first+1 2^64 + w_first+2 2^32 + w_first+3), in 32-bit limbs,
  // least significant first; P 2^(e - 32 first - 128) = x 2/pi minus whole turns, to 94 or
  // more fraction bits.
  std::uint64_t limb[5] = {};
  for (int k = 0; k < 4; ++k) {
    std::uint64_t product = m * kTwoOverPi[first + 3 - k];
    for (int i = k; i < 5 && product != 0; ++i) {
      product += limb[i];
      limb[i] = product & 0xFFFFFFFFu;
      product >>= 32;
    }
  }
  // Bit `one` of P has weight 1.
  const int one = 128 + 32 * first - e;
  // P in 64-bit words, with a zero word above, and the 64 bits of P from bit `lowest` up
  // (30 <= lowest <= 152).
  const std::uint64_t word[4] = {limb[0] | (limb[1] << 32), limb[2] | (limb[3] << 32), limb[4], 0};
  auto bitsFrom = [&](int lowest) {
    const int w = lowest / 64, shift = lowest % 64;
    return shift == 0 ? word[w] : (word[w] >> shift) | (word[w + 1] << (64 - shift));
  };
  unsigned quadrant = static_cast<unsigned>(bitsFrom(one) & 3u);
  std::uint64_t fraction = bitsFrom(one - 64);  // the fraction of a quadrant, times 2^64
  if ((fraction >> 63) != 0) ++quadrant;        // round to the nearest quadrant
  // As a signed fraction of a quadrant in [-1/2, 1/2): two's complement does the rounding.
  const auto signedFraction = static_cast<std::int64_t>(fraction);
  double r = static_cast<double>(signedFraction) * 0x1p-64 * kPiOver2;
  if (negative) {
    r = -r;
    quadrant = 0u - quadrant;
  }
  return {r, quadrant & 3u};
}

// sin r and cos r for |r| <= pi/4: Taylor to r^15 and r^16 (the next terms are below
// 2^-54 and 2^-59 of the result).
double sinPoly(double r) {
  const double z = r * r;
  const double p =
      -1.0 / 6.0 +
      z * (1.0 / 120.0 + z * (-1.0 / 5040.0 +
                              z * (1.0 / 362880.0 +
                                   z * (-1.0 / 39916800.0 +
                                        z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0))))));
  return r + r * z * p;
}

double cosPoly(double r) {
  const double z = r * r;
  const double p =
      1.0 / 24.0 +
      z * (-1.0 / 720.0 +
           z * (1.0 / 40320.0 + z * (-1.0 / 3628800.0 + z * (1.0 / 479001600.0 +
                                                             z * (-1.0 / 87178291200.0 +
                                                                  z * (1.0 / 20922789888000.0))))));
  return 1.0 - 0.5 * z + z * z * p;
}

// sin x, or cos x when `cosine`: one quadrant table for both.
float sinOrCos(float x, bool cosine) {
  if (!std::isfinite(x)) return x - x;      // NaN for NaN and for either infinity
  if (x == 0.0f) return cosine ? 1.0f : x;  // sin(-0) is -0, which -0 + -0 * ... is not
  double r = static_cast<double>(x);
  unsigned quadrant = 0;
  if (std::fabs(r) > kPiOver4) {
    const Reduced red = reduce(x);
    r = red.r;
    quadrant = red.quadrant;
  }
  if (cosine) quadrant = (quadrant + 1) & 3u;  // cos x = sin(x + pi/2)
  double y = 0.0;
  switch (quadrant) {
    case 0:
      y = sinPoly(r);
      break;
    case 1:
      y = cosPoly(r);
      break;
    case 2:
      y = -sinPoly(r);
      break;
    default:
      y = -cosPoly(r);
      break;
  }
  return static_cast<float>(y);
}

// atan(t) for 0 <= t (t may be infinite), in double.
double atanPositive(double t) {
  double base = 0.0;
  bool complement = false;
  if (t > 1.0) {  // atan t = pi/2 - atan(1/t)
    t = 1.0 / t;
    complement = true;
  }
  if (t > kTanPiOver12) {  // atan t = pi/6 + atan((sqrt3 t - 1) / (sqrt3 + t))
    t = (kSqrt3 * t - 1.0) / (kSqrt3 + t);
    base = kPiOver6;
  }
  // |t| <= tan(pi/12): t^2 <= 0.072, so 14 terms reach 2^-58 of the result.
  const double z = t * t;
  double p = -1.0 / 27.0;
  p = 1.0 / 25.0 + z * p;
  p = -1.0 / 23.0 + z * p;
  p = 1.0 / 21.0 + z * p;
  p = -1.0 / 19.0 + z * p;
  p = 1.0 / 17.0 + z * p;
  p = -1.0 / 15.0 + z * p;
  p = 1.0 / 13.0 + z * p;
  p = -1.0 / 11.0 + z * p;
  p = 1.0 / 9.0 + z * p;
  p = -1.0 / 7.0 + z * p;
  p = 1.0 / 5.0 + z * p;
  p = -1.0 / 3.0 + z * p;
  const double a = base + (t + t * z * p);
  return complement ? kPiOver2 - a : a;
}

// pi/2 in three parts (Cody and Waite): the first two have short mantissas, so k times each
// is exact in double for |k| < 2^20, and r = x - k pi/2 loses nothing to cancellation for
// the angles of the fast path (|k| <= 63,662). The parts were computed from pi to 80 digits.
constexpr double kPiOver2Part1 = 0x1.921fb544p+0;
constexpr double kPiOver2Part2 = 0x1.0b4611a6p-34;
constexpr double kPiOver2Part3 = 0x1.3198a2e037073p-69;
constexpr double kTwoOverPiDouble = 0x1.45f306dc9c883p-1;

}  // namespace

// portableCosSin past the fast path's range. Out of line, so that the fast path saves no
// registers for its calls.
namespace {
[[gnu::noinline]] CosSin accurateCosSin(float radians) noexcept {
  return {portableCos(radians), portableSin(radians)};
}

// The fast path's angle x (|x| <= kFastTrigLimit) as r + k pi/2 with |r| <= pi/4 (plus
// rounding); k's two low bits are the quadrant.
struct QuarterTurns {
  double r;
  std::uint32_t quadrant;
};

inline QuarterTurns reduceToQuarterTurns(double x) noexcept {
  // The nearest multiple of pi/2: adding and subtracting 1.5 * 2^52 leaves the nearest
  // integer (|t| < 2^16), exactly and on every IEEE platform, and the sum's low bits are
  // k's. Ties go to even where a truncation after adding a signed half would round them
  // away from zero; on no float of the fast path does that change a result (checked on all
  // of them, docs/narrow-phase.md, "Shorter chains, same bits").
  const double t = x * kTwoOverPiDouble;
  const double shifted = t + 0x1.8p52;
  const double kd = shifted - 0x1.8p52;
  std::uint64_t shiftedBits = 0;
  std::memcpy(&shiftedBits, &shifted, sizeof shiftedBits);
  const double r = ((x - kd * kPiOver2Part1) - kd * kPiOver2Part2) - kd * kPiOver2Part3;
  return {r, static_cast<std::uint32_t>(shiftedBits) & 3u};
}

}  // namespace

// |r| <= pi/4 (plus rounding): Taylor to r^11 for sine and r^12 for cosine truncate below
// 2^-37 and 2^-45 relative ((pi/4)^13 / 13!, (pi/4)^14 / 14!), far below a float ulp.
// The scalar form, by Horner's rule: every target without SSE2 (aarch64, wasm) runs it.
CosSin detail::portableCosSinScalar(float radians) noexcept {
  if (radians == 0.0f) return {1.0f, radians};  // sin(-0) is -0, which -0 + -0 * ... is not
  const double x = static_cast<double>(radians);
  // NaN fails the comparison and goes the accurate way too.
  if (!(std::fabs(x) <= static_cast<double>(kFastTrigLimit))) return accurateCosSin(radians);
  const auto [r, quadrant] = reduceToQuarterTurns(x);
  const double z = r * r;
  const double sinR =
      r +
      r * z *
          (-1.0 / 6.0 + z * (1.0 / 120.0 +
                             z * (-1.0 / 5040.0 + z * (1.0 / 362880.0 + z * (-1.0 / 39916800.0)))));
  const double cosR =
      1.0 +
      z * (-0.5 + z * (1.0 / 24.0 +
                       z * (-1.0 / 720.0 + z * (1.0 / 40320.0 + z * (-1.0 / 3628800.0 +
                                                                     z * (1.0 / 479001600.0))))));
  const float c = static_cast<float>(cosR);
  const float s = static_cast<float>(sinR);
  // By quadrant: (c, s), (-s, c), (-c, -s), (s, -c). Formed with a swap and two sign flips
  // on the bits (negation is exact, so the same floats) rather than a switch, whose
  // branch random angles mispredict three times in four.
  const std::uint32_t swap = 0u - (quadrant & 1u);
  std::uint32_t cBits = 0;
  std::uint32_t sBits = 0;
  std::memcpy(&cBits, &c, sizeof cBits);  // not std::bit_cast, as in reduce
  std::memcpy(&sBits, &s, sizeof sBits);
  const std::uint32_t first = (sBits & swap) | (cBits & ~swap);
  const std::uint32_t second = (cBits & swap) | (sBits & ~swap);
  const std::uint32_t negateFirst = ((quadrant + 1u) & 2u) << 30;  // quadrants 1 and 2
  const std::uint32_t negateSecond = (quadrant & 2u) << 30;        // quadrants 2 and 3
  const std::uint32_t cosBits = first ^ negateFirst;
  const std::uint32_t sinBits = second ^ negateSecond;
  CosSin out;
  std::memcpy(&out.cosine, &cosBits, sizeof cosBits);
  std::memcpy(&out.sine, &sinBits, sizeof sinBits);
  return out;
}

CosSin portableCosSin(float radians) noexcept {
#if defined(__SSE2__)
  if (radians == 0.0f) return {1.0f, radians};  // as in portableCosSinScalar
  const double x = static_cast<double>(radians);
  if (!(std::fabs(x) <= static_cast<double>(kFastTrigLimit))) return accurateCosSin(radians);
  const auto [r, quadrant] = reduceToQuarterTurns(x);
  const double z = r * r;
  // Both polynomials at once, cosine in the low lane and sine in the high one, by Estrin's
  // scheme: (c2 + c4 z) + z^2 (c6 + c8 z) + z^4 (c10 + c12 z), the sine's lane (c3 + c5 z)
  // + z^2 (c7 + c9 z) + z^4 (c11 + 0 z). A shorter chain than Horner's rule, with other
  // roundings in double, but the same float: on every float of the fast path the result
  // equals portableCosSinScalar's, bit for bit (checked on all of them; the tests check a
  // sample on every build).
  const __m128d zz = _mm_set1_pd(z);
  const __m128d z2 = _mm_mul_pd(zz, zz);
  const __m128d z4 = _mm_mul_pd(z2, z2);
  const __m128d p01 =
      _mm_add_pd(_mm_set_pd(-1.0 / 6.0, -0.5), _mm_mul_pd(zz, _mm_set_pd(1.0 / 120.0, 1.0 / 24.0)));
  const __m128d p23 = _mm_add_pd(_mm_set_pd(-1.0 / 5040.0, -1.0 / 720.0),
                                 _mm_mul_pd(zz, _mm_set_pd(1.0 / 362880.0, 1.0 / 40320.0)));
  const __m128d p45 = _mm_add_pd(_mm_set_pd(-1.0 / 39916800.0, -1.0 / 3628800.0),
                                 _mm_mul_pd(zz, _mm_set_pd(0.0, 1.0 / 479001600.0)));
  const __m128d p = _mm_add_pd(_mm_add_pd(p01, _mm_mul_pd(z2, p23)), _mm_mul_pd(z4, p45));
  // cos = 1 + z p, sin = r + (r z) p.
  const __m128d both = _mm_add_pd(_mm_set_pd(r, 1.0), _mm_mul_pd(_mm_set_pd(r * z, z), p));
  const __m128 cs = _mm_cvtpd_ps(both);  // (c, s, 0, 0), each rounded as static_cast
  // By quadrant: (c, s), (-s, c), (-c, -s), (s, -c): a swap chosen by a mask and two sign
  // flips from a table (negation is exact), no branch.
  const __m128 sc = _mm_shuffle_ps(cs, cs, _MM_SHUFFLE(3, 2, 0, 1));
  const __m128 swap = _mm_castsi128_ps(_mm_set1_epi32(-static_cast<int>(quadrant & 1u)));
  const __m128 swapped = _mm_or_ps(_mm_and_ps(swap, sc), _mm_andnot_ps(swap, cs));
  alignas(16) static constexpr std::uint32_t kSigns[4][4] = {{0u, 0u, 0u, 0u},
                                                             {0x80000000u, 0u, 0u, 0u},
                                                             {0x80000000u, 0x80000000u, 0u, 0u},
                                                             {0u, 0x80000000u, 0u, 0u}};
  const __m128 signs = _mm_load_ps(reinterpret_cast<const float*>(kSigns[quadrant]));
  const __m128 result = _mm_xor_ps(swapped, signs);
  // The two low lanes are the answer (cosine, sine) as CosSin lays them out.
  static_assert(sizeof(CosSin) == 2 * sizeof(float));
  CosSin out;
  _mm_storel_pi(reinterpret_cast<__m64*>(&out), result);
  return out;
#else
  return detail::portableCosSinScalar(radians);
#endif
}

float portableSin(float radians) noexcept {
  return sinOrCos(radians, false);
}

float portableCos(float radians) noexcept {
  return sinOrCos(radians, true);
}

float portableAtan(float x) noexcept {
  if (std::isnan(x)) return x + x;
  const double a = atanPositive(std::fabs(static_cast<double>(x)));
  return static_cast<float>(std::copysign(a, static_cast<double>(x)));
}

float portableAtan2(float y, float x) noexcept {
  if (std::isnan(x) || std::isnan(y)) return x + y;
  const double dy = static_cast<double>(y);
  const double dx = static_cast<double>(x);
  const double ay = std::fabs(dy);
  const double ax = std::fabs(dx);
  const bool left = std::signbit(dx);  // x < 0 or x = -0: the angle is measured past pi/2
  double a = 0.0;
  if (ay == 0.0) {
    a = left ? kPi : 0.0;
  } else if (std::isinf(ax) && std::isinf(ay)) {
    a = left ? 3.0 * kPiOver4 : kPiOver4;
  } else if (ax == 0.0 || std::isinf(ay)) {
    a = kPiOver2;
  } else if (std::isinf(ax)) {
    a = left ? kPi : 0.0;
  } else {
    a = ay <= ax ? atanPositive(ay / ax) : kPiOver2 - atanPositive(ax / ay);
    if (left) a = kPi - a;
  }
  return static_cast<float>(std::copysign(a, dy));
}

}  // namespace quack
