#pragma once
// The snapshot byte codec that the 2D world's snapshots (snapshot.cpp) and the 3D world's
// (snapshot3.cpp) share: little-endian numbers, floats as their IEEE bits, LEB128 counts,
// and a reader that checks every count and index against what is left and keeps the first
// problem, naming the field and the byte. Private to the world layer.

#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "quack/math/aabb.hpp"
#include "quack/math/transform.hpp"

namespace quack::detail {

static_assert(std::numeric_limits<float>::is_iec559 && sizeof(float) == 4,
              "snapshots store floats as IEEE 754 binary32 bits");

// std::bit_cast, which emscripten 3.1.6's libc++ (the web build) lacks.
template <class To, class From>
inline To bitCast(const From& from) noexcept {
  static_assert(sizeof(To) == sizeof(From));
  To to;
  std::memcpy(&to, &from, sizeof to);
  return to;
}

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

inline std::uint64_t fnv1a(std::span<const std::uint8_t> bytes, std::uint64_t h = kFnvOffset) {
  for (std::uint8_t b : bytes) {
    h ^= b;
    h *= kFnvPrime;
  }
  return h;
}

// ---- writing ---------------------------------------------------------------------------

class Writer {
 public:
  std::vector<std::uint8_t> bytes;

  void u8(std::uint8_t v) { bytes.push_back(v); }
  void flag(bool v) { u8(v ? 1 : 0); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i)
      bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i)
      bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f32(float v) { u32(bitCast<std::uint32_t>(v)); }
  void f64(double v) { u64(bitCast<std::uint64_t>(v)); }
  void vec(Vec2 v) {
    f32(v.x);
    f32(v.y);
  }
  void xf(Transform t) {
    vec(t.p);
    f32(t.q.c);
    f32(t.q.s);
  }
  void box(Aabb b) {
    vec(b.lower);
    vec(b.upper);
  }
  // Counts and indices: LEB128, seven bits a byte, low first (most are below 128).
  void var(std::uint32_t v) {
    while (v >= 0x80u) {
      bytes.push_back(static_cast<std::uint8_t>((v & 0x7fu) | 0x80u));
      v >>= 7;
    }
    bytes.push_back(static_cast<std::uint8_t>(v));
  }
  void size(std::size_t n) { var(static_cast<std::uint32_t>(n)); }
  void list(const std::vector<std::uint32_t>& v) {
    size(v.size());
    for (std::uint32_t x : v)
      var(x);
  }
};

// ---- reading ---------------------------------------------------------------------------

// Reads numbers with bounds checks. The first problem is kept (naming the field and the
// byte offset); after it every read returns zero, so loops over counts end at once.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, const char* section)
      : bytes_(bytes), section_(section) {}

  bool ok() const noexcept { return error_.empty(); }
  const std::string& error() const noexcept { return error_; }
  std::size_t left() const noexcept { return bytes_.size() - pos_; }
  bool atEnd() const noexcept { return pos_ == bytes_.size(); }

  void fail(const std::string& what) {
    if (error_.empty())
      error_ = std::string(section_) + " section, byte " + std::to_string(pos_) + ": " + what;
  }

  std::uint8_t u8(const char* what) {
    if (!take(1, what)) return 0;
    return bytes_[pos_ - 1];
  }
  bool flag(const char* what) {
    const std::uint8_t v = u8(what);
    if (v > 1) fail(std::string(what) + " is " + std::to_string(v) + ", not 0 or 1");
    return v == 1;
  }
  std::uint32_t u32(const char* what) {
    if (!take(4, what)) return 0;
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= static_cast<std::uint32_t>(bytes_[pos_ - 4 + static_cast<std::size_t>(i)]) << (8 * i);
    return v;
  }
  std::uint64_t u64(const char* what) {
    if (!take(8, what)) return 0;
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i)
      v |= static_cast<std::uint64_t>(bytes_[pos_ - 8 + static_cast<std::size_t>(i)]) << (8 * i);
    return v;
  }
  std::int32_t i32(const char* what) { return static_cast<std::int32_t>(u32(what)); }
  // A count or index (Writer::var): at most five bytes, the fifth holding the top 4 bits.
  std::uint32_t var(const char* what) {
    std::uint32_t v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
      const std::uint8_t b = u8(what);
      if (shift == 28 && b > 0x0f) {
        fail(std::string(what) + " does not fit 32 bits");
        return 0;
      }
      v |= static_cast<std::uint32_t>(b & 0x7fu) << shift;
      if ((b & 0x80u) == 0) return v;
    }
    return 0;
  }
  // Every float a world holds is finite; anything else is corruption.
  float f32(const char* what) {
    const float v = bitCast<float>(u32(what));
    if (!isFinite(v)) {
      fail(std::string(what) + " is not finite");
      return 0.0f;
    }
    return v;
  }
  double f64(const char* what) {
    const double v = bitCast<double>(u64(what));
    if (!(v - v == 0.0)) {
      fail(std::string(what) + " is not finite");
      return 0.0;
    }
    return v;
  }
  Vec2 vec(const char* what) {
    const float x = f32(what);
    return {x, f32(what)};
  }
  Transform xf(const char* what) {
    Transform t;
    t.p = vec(what);
    t.q.c = f32(what);
    t.q.s = f32(what);
    return t;
  }
  Aabb box(const char* what) {
    Aabb b;
    b.lower = vec(what);
    b.upper = vec(what);
    return b;
  }
  // A count of items of at least `minBytes` each: checked against the bytes left, so a
  // corrupted count fails here instead of allocating.
  std::uint32_t count(const char* what, std::size_t minBytes) {
    const std::uint32_t n = var(what);
    if (!ok()) return 0;
    if (static_cast<std::uint64_t>(n) * minBytes > left()) {
      fail(std::string(what) + " " + std::to_string(n) + " needs at least " +
           std::to_string(static_cast<std::uint64_t>(n) * minBytes) + " bytes, " +
           std::to_string(left()) + " left");
      return 0;
    }
    return n;
  }
  // An index below `limit`.
  std::uint32_t index(const char* what, std::size_t limit) {
    const std::uint32_t i = var(what);
    if (!ok()) return 0;
    if (i >= limit) {
      fail(std::string(what) + " " + std::to_string(i) + " is out of range (" +
           std::to_string(limit) + ")");
      return 0;
    }
    return i;
  }
  std::vector<std::uint32_t> indexList(const char* what, std::size_t limit) {
    std::vector<std::uint32_t> v(count(what, 1));
    for (std::uint32_t& x : v)
      x = index(what, limit);
    return v;
  }

 private:
  bool take(std::size_t n, const char* what) {
    if (!ok()) return false;
    if (left() < n) {
      fail("truncated while reading " + std::string(what) + " (" + std::to_string(n) +
           " bytes needed, " + std::to_string(left()) + " left)");
      return false;
    }
    pos_ += n;
    return true;
  }

  std::span<const std::uint8_t> bytes_;
  const char* section_;
  std::size_t pos_ = 0;
  std::string error_;
};

}  // namespace quack::detail
