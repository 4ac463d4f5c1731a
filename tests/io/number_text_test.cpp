#include "quack/io/number_text.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace quack {
namespace {

std::string toChars(double x) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  EXPECT_EQ(ec, std::errc{});
  return std::string(buf, end);
}

std::string portable(double x) {
  std::string out;
  detail::appendShortestPortable(out, x);
  return out;
}

// The portable printer (what the WebAssembly build uses) against the standard library's
// shortest round-trip std::to_chars, which native builds use: byte for byte the same.
int countMismatches(const std::vector<double>& values) {
  int mismatches = 0;
  for (double x : values) {
    const std::string expected = toChars(x);
    const std::string got = portable(x);
    if (got != expected && ++mismatches <= 10) {
      ADD_FAILURE() << "bits " << std::hex << std::bit_cast<std::uint64_t>(x) << ": to_chars "
                    << expected << ", portable " << got;
    }
  }
  return mismatches;
}

TEST(NumberText, HandPickedValues) {
  EXPECT_EQ(portable(0.0), "0");
  EXPECT_EQ(portable(-0.0), "-0");
  EXPECT_EQ(portable(1.0), "1");
  EXPECT_EQ(portable(-2.5), "-2.5");
  EXPECT_EQ(portable(100.0), "100");
  EXPECT_EQ(portable(0.1), "0.1");
  EXPECT_EQ(portable(static_cast<double>(0.1f)), "0.10000000149011612");
  EXPECT_EQ(portable(1e22), "1e+22");
  EXPECT_EQ(portable(1e-7), "1e-07");
  EXPECT_EQ(portable(0.0001), "1e-04");  // shorter than 0.0001
  EXPECT_EQ(portable(0.001), "0.001");   // as long as 1e-03: fixed wins the tie
  EXPECT_EQ(portable(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(portable(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(portable(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(portable(-std::numeric_limits<double>::quiet_NaN()), "-nan");
  EXPECT_EQ(portable(std::numeric_limits<double>::denorm_min()), "5e-324");
  EXPECT_EQ(portable(std::numeric_limits<double>::max()), "1.7976931348623157e+308");
  // A whole number printed in full: the exact integer, as std::to_chars does.
  EXPECT_EQ(portable(12345678901234567890.0), "12345678901234567168");
  EXPECT_EQ(countMismatches({0.0, -0.0, 1.0, 0.1, 1e22, 1e23, 5e-324, 9007199254740993.0,
                             12345678901234567890.0, 123456789012345680000.0, 0.3, 2.0 / 3.0}),
            0);
}

TEST(NumberText, RandomDoublesMatchToChars) {
  std::mt19937_64 rng(19);
  std::vector<double> values;
  for (int i = 0; i < 40000; ++i) {  // every bit pattern: subnormals, NaNs, infinities too
    values.push_back(std::bit_cast<double>(rng()));
  }
  EXPECT_EQ(countMismatches(values), 0);
}

TEST(NumberText, RandomFloatsWidenedMatchToChars) {
  // What state files print: floats widened to double, over every exponent.
  std::mt19937 rng(1919);
  std::vector<double> values;
  for (int i = 0; i < 40000; ++i) {
    values.push_back(static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(rng()))));
  }
  // And the ordinary range of a simulation, where fixed and scientific trade places.
  std::uniform_real_distribution<float> exponent(-12.0f, 12.0f);
  for (int i = 0; i < 20000; ++i) {
    const float x = std::pow(10.0f, exponent(rng)) * (rng() % 2 == 0 ? 1.0f : -1.0f);
    values.push_back(static_cast<double>(x));
  }
  EXPECT_EQ(countMismatches(values), 0);
}

TEST(NumberText, EdgesOfTheNotationsMatchToChars) {
  // Powers of two and ten and their neighbours: where the rounding interval is lopsided,
  // where the digit count changes and where fixed and scientific have equal length.
  std::vector<double> values;
  for (int e = -1074; e <= 1023; ++e) {
    const double p = std::ldexp(1.0, e);
    values.push_back(p);
    values.push_back(std::nextafter(p, 0.0));
    values.push_back(std::nextafter(p, 1e308));
    values.push_back(static_cast<double>(std::ldexp(1.0f, std::max(-149, std::min(e, 127)))));
  }
  for (int e = -323; e <= 308; ++e) {
    const double p = std::strtod(("1e" + std::to_string(e)).c_str(), nullptr);
    values.push_back(p);
    values.push_back(std::nextafter(p, 0.0));
    values.push_back(std::nextafter(p, 1e308));
    values.push_back(-p * 1.5);
  }
  for (std::uint64_t whole = 1; whole < 100000; whole = whole * 3 + 1) {
    values.push_back(static_cast<double>(whole));
    values.push_back(static_cast<double>(whole) * 1e17);
  }
  EXPECT_EQ(countMismatches(values), 0);
}

TEST(NumberText, AppendShortestReadsBack) {
  std::mt19937 rng(7);
  for (int i = 0; i < 10000; ++i) {
    const double x = static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(rng())));
    if (!std::isfinite(x)) continue;
    std::string out = "prefix ";
    appendShortest(out, x);
    ASSERT_EQ(out.rfind("prefix ", 0), 0u);
    EXPECT_EQ(std::strtod(out.c_str() + 7, nullptr), x) << out;
  }
}

}  // namespace
}  // namespace quack
