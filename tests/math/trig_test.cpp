#include "quack/math/trig.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "quack/math/rot.hpp"

namespace quack {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// |got - exact| in units of the float spacing at `exact` (the C library's double result
// stands for the exact value: it is within a double ulp, 2^-29 of a float ulp).
double ulpError(float got, double exact) {
  const float nearest = static_cast<float>(exact);
  const float mag = std::fabs(nearest);
  double ulp = static_cast<double>(std::nextafter(mag, kInf) - mag);
  if (mag == 0.0f || !std::isfinite(ulp)) ulp = static_cast<double>(std::nextafter(0.0f, 1.0f));
  return std::fabs(static_cast<double>(got) - exact) / ulp;
}

struct Accuracy {
  double maxUlp = 0.0;
  float worstArgument = 0.0f;
  int notNearest = 0;  // results that are not the float nearest the exact value
  int count = 0;
};

template <class Ours, class Exact>
Accuracy measure(const std::vector<float>& xs, Ours ours, Exact exact) {
  Accuracy a;
  for (float x : xs) {
    const float got = ours(x);
    const double want = exact(static_cast<double>(x));
    const double err = ulpError(got, want);
    if (err > a.maxUlp) {
      a.maxUlp = err;
      a.worstArgument = x;
    }
    a.notNearest += got != static_cast<float>(want);
    ++a.count;
  }
  return a;
}

void report(const char* name, const Accuracy& a) {
  std::printf("%s: %d arguments, largest error %.4f ulp (at %.9g), %d not the nearest float\n",
              name, a.count, a.maxUlp, static_cast<double>(a.worstArgument), a.notNearest);
}

// Angles a simulation meets, a wide range, and every finite float (random bit patterns,
// so huge and subnormal arguments are covered).
std::vector<float> arguments(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<float> xs;
  std::uniform_real_distribution<float> small(-7.0f, 7.0f), wide(-1e5f, 1e5f);
  for (int i = 0; i < 100000; ++i)
    xs.push_back(small(rng));
  for (int i = 0; i < 50000; ++i)
    xs.push_back(wide(rng));
  while (xs.size() < 250000) {
    const float x = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    if (std::isfinite(x)) xs.push_back(x);
  }
  // Multiples of pi/2 as floats: the results are tiny and reduction must be exact.
  for (int k = -2000; k <= 2000; ++k) {
    xs.push_back(static_cast<float>(k * 1.5707963267948966));
  }
  for (float big : {1e10f, 1e20f, 1e30f, 3.4e38f, -3.4e38f, 16777216.0f, 8.5070592e37f}) {
    xs.push_back(big);
  }
  return xs;
}

TEST(Trig, SinAndCosWithinHalfAnUlpPlusABit) {
  const std::vector<float> xs = arguments(19);
  const Accuracy s = measure(xs, portableSin, [](double x) { return std::sin(x); });
  const Accuracy c = measure(xs, portableCos, [](double x) { return std::cos(x); });
  report("sin", s);
  report("cos", c);
  // Double-precision evaluation rounded once to float: at most half an ulp and the double
  // evaluation's error (2^-50 relative is 2^-26 ulp); a wrong reduction shows as millions.
  EXPECT_LT(s.maxUlp, 0.5001);
  EXPECT_LT(c.maxUlp, 0.5001);
  // Not the nearest float only when the exact value is within ~2^-26 ulp of a midpoint.
  EXPECT_LE(s.notNearest, 2);
  EXPECT_LE(c.notNearest, 2);
}

TEST(Trig, AtanAndAtan2WithinHalfAnUlpPlusABit) {
  const std::vector<float> xs = arguments(20);
  const Accuracy a = measure(xs, portableAtan, [](double x) { return std::atan(x); });
  report("atan", a);
  EXPECT_LT(a.maxUlp, 0.5001);
  EXPECT_LE(a.notNearest, 2);

  std::mt19937 rng(21);
  std::uniform_real_distribution<float> coord(-10.0f, 10.0f);
  Accuracy b;
  auto check = [&](float y, float x) {
    const float got = portableAtan2(y, x);
    const double want = std::atan2(static_cast<double>(y), static_cast<double>(x));
    const double err = ulpError(got, want);
    if (err > b.maxUlp) b.maxUlp = err;
    b.notNearest += got != static_cast<float>(want);
    ++b.count;
  };
  for (int i = 0; i < 150000; ++i)
    check(coord(rng), coord(rng));
  for (int i = 0; i < 100000; ++i) {
    const float y = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    const float x = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
    if (std::isfinite(x) && std::isfinite(y)) check(y, x);
  }
  report("atan2", b);
  EXPECT_LT(b.maxUlp, 0.5001);
  EXPECT_LE(b.notNearest, 2);
}

bool sameBits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

TEST(Trig, SpecialValuesAsTheCStandardSays) {
  EXPECT_TRUE(sameBits(portableSin(0.0f), 0.0f));
  EXPECT_TRUE(sameBits(portableSin(-0.0f), -0.0f));
  EXPECT_EQ(portableCos(0.0f), 1.0f);
  EXPECT_EQ(portableCos(-0.0f), 1.0f);
  EXPECT_EQ(portableSin(1e-30f), 1e-30f);  // sin x = x to the last bit for tiny x
  EXPECT_EQ(portableSin(std::nextafter(0.0f, 1.0f)), std::nextafter(0.0f, 1.0f));
  for (float bad : {kNaN, kInf, -kInf}) {
    EXPECT_TRUE(std::isnan(portableSin(bad)));
    EXPECT_TRUE(std::isnan(portableCos(bad)));
  }
  EXPECT_TRUE(std::isnan(portableAtan(kNaN)));
  EXPECT_TRUE(std::isnan(portableAtan2(kNaN, 1.0f)));
  EXPECT_TRUE(std::isnan(portableAtan2(1.0f, kNaN)));
  EXPECT_TRUE(sameBits(portableAtan(-0.0f), -0.0f));
  EXPECT_EQ(portableAtan(kInf), static_cast<float>(std::atan(INFINITY)));
  EXPECT_EQ(portableAtan(-kInf), -portableAtan(kInf));

  // atan2: every special pair of C11 F.10.1.4, against the C library's double atan2
  // rounded to float (glibc's atan2f(-3e38, -1) is -1.57079625, 0.64 ulp from the exact
  // -pi/2 - 3.3e-39; the nearest float is -1.57079637).
  const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, kInf, -kInf, 1e-45f, -3e38f};
  for (float y : specials) {
    for (float x : specials) {
      const auto want =
          static_cast<float>(std::atan2(static_cast<double>(y), static_cast<double>(x)));
      EXPECT_TRUE(sameBits(portableAtan2(y, x), want)) << "atan2(" << y << ", " << x << ")";
    }
  }
  const float pi = static_cast<float>(3.141592653589793);
  EXPECT_EQ(portableAtan2(0.0f, -1.0f), pi);  // Rot::angle of a half turn
  EXPECT_EQ(portableAtan2(-0.0f, -1.0f), -pi);
}

// The fast pair (Rot::fromAngle's): within 1 float ulp of the exact values on the fast path
// (|x| <= kFastTrigLimit), and exactly portableCos / portableSin beyond it, for NaN and the
// infinities. Checked against the C library's double sin and cos, an independent method.
TEST(Trig, CosSinWithinOneUlpOnTheFastPathAndExactBeyond) {
  std::mt19937 rng(31);
  std::vector<float> xs;
  std::uniform_real_distribution<float> small(-7.0f, 7.0f), scene(-1e4f, 1e4f),
      fast(-kFastTrigLimit, kFastTrigLimit);
  for (int i = 0; i < 200000; ++i)
    xs.push_back(small(rng));
  for (int i = 0; i < 100000; ++i)
    xs.push_back(scene(rng));
  for (int i = 0; i < 100000; ++i)
    xs.push_back(fast(rng));
  for (int k = -2000; k <= 2000; ++k) {  // next to multiples of pi/2 the results are tiny
    const float x = static_cast<float>(k * 1.5707963267948966);
    for (float y : {x, std::nextafter(x, kInf), std::nextafter(x, -kInf)})
      xs.push_back(y);
  }
  for (float x : {0.0f, -0.0f, 1e-30f, -1e-30f, 1e-8f, kFastTrigLimit, -kFastTrigLimit})
    xs.push_back(x);
  const Accuracy c = measure(
      xs, [](float x) { return portableCosSin(x).cosine; }, [](double x) { return std::cos(x); });
  const Accuracy s = measure(
      xs, [](float x) { return portableCosSin(x).sine; }, [](double x) { return std::sin(x); });
  report("portableCosSin cosine", c);
  report("portableCosSin sine", s);
  EXPECT_LE(c.maxUlp, 1.0);
  EXPECT_LE(s.maxUlp, 1.0);
  // Mostly the nearest float: the polynomial errors are far below an ulp.
  EXPECT_LT(c.notNearest, c.count / 100);
  EXPECT_LT(s.notNearest, s.count / 100);
  EXPECT_EQ(portableCosSin(0.0f).cosine, 1.0f);
  EXPECT_EQ(std::bit_cast<std::uint32_t>(portableCosSin(-0.0f).sine),
            std::bit_cast<std::uint32_t>(-0.0f));
  // Beyond the fast path: the accurate functions' bits.
  for (float x : {std::nextafter(kFastTrigLimit, kInf), -2e5f, 1e10f, 3.4e38f, kInf, -kInf, kNaN}) {
    const CosSin cs = portableCosSin(x);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(cs.cosine), std::bit_cast<std::uint32_t>(portableCos(x)))
        << x;
    EXPECT_EQ(std::bit_cast<std::uint32_t>(cs.sine), std::bit_cast<std::uint32_t>(portableSin(x)))
        << x;
  }
}

// x86's SSE2 form of portableCosSin (Estrin's scheme, two lanes) and the scalar form every
// other target runs (Horner's rule) round differently in double but must give the same
// floats. All 2.4e9 floats of the fast path agree (checked once by hand, docs/narrow-phase.md);
// here every 4,099th float bit pattern up to the limit, both signs, and the floats next to
// the half-way points between multiples of pi/2, where the two reductions could round k apart.
TEST(Trig, CosSinSse2FormGivesTheScalarFormsBits) {
  int checked = 0;
  int differ = 0;
  auto check = [&](float x) {
    const CosSin fast = portableCosSin(x);
    const CosSin scalar = detail::portableCosSinScalar(x);
    ++checked;
    if (std::bit_cast<std::uint32_t>(fast.cosine) != std::bit_cast<std::uint32_t>(scalar.cosine) ||
        std::bit_cast<std::uint32_t>(fast.sine) != std::bit_cast<std::uint32_t>(scalar.sine)) {
      if (++differ <= 5) ADD_FAILURE() << "portableCosSin differs from the scalar form at " << x;
    }
  };
  const std::uint32_t limitBits = std::bit_cast<std::uint32_t>(kFastTrigLimit);
  for (std::uint32_t bits = 0; bits <= limitBits; bits += 4099u) {
    check(std::bit_cast<float>(bits));
    check(-std::bit_cast<float>(bits));
  }
  for (int k = -63662; k <= 63662; k += 7) {
    float x = static_cast<float>((k + 0.5) * 1.5707963267948966);
    for (int step = 0; step < 3; ++step) {
      check(x);
      x = std::nextafter(x, kInf);
    }
  }
  EXPECT_GT(checked, 600000);
  EXPECT_EQ(differ, 0);
}

TEST(Trig, RotRoundTripsThroughItsAngle) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> angle(-3.14159f, 3.14159f);
  for (int i = 0; i < 10000; ++i) {
    const float a = angle(rng);
    const Rot q = Rot::fromAngle(a);
    EXPECT_NEAR(q.c * q.c + q.s * q.s, 1.0f, 2e-7f);
    EXPECT_NEAR(q.angle(), a, 4e-7f) << a;
  }
  EXPECT_EQ(Rot::fromAngle(0.0f), Rot{});
}

// The same bits on every build: a hash of many results, pinned. A build whose maths
// differs anywhere (a C library call, a contracted multiply-add, long double) fails here.
TEST(Trig, GoldenHashTiesTheBuildsTogether) {
  const std::vector<float> xs = arguments(23);
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](float v) {
    h ^= std::bit_cast<std::uint32_t>(v);
    h *= 1099511628211ull;
  };
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const CosSin cs = portableCosSin(xs[i]);
    mix(cs.cosine);
    mix(cs.sine);
    mix(portableSin(xs[i]));
    mix(portableCos(xs[i]));
    mix(portableAtan(xs[i]));
    mix(portableAtan2(xs[i], xs[xs.size() - 1 - i]));
  }
  std::printf("trig golden hash: 0x%016llx\n", static_cast<unsigned long long>(h));
  EXPECT_EQ(h, 0x344d93eb03100e9aull);
}

}  // namespace
}  // namespace quack
