#pragma once
// Lanes for the contact solver (docs/world.md, "The solver's data"): a float per lane and
// the handful of operations the solver needs, on every path Quack builds:
//
//   FloatS  one lane, plain C++ (the portable path; WebAssembly uses it)
//   FloatW  the path chosen at build time (QUACK_SIMD): four SSE2 lanes on x86-64, eight
//           AVX2 lanes with QUACK_SIMD=avx2, four NEON lanes on AArch64, or FloatS.
//
// Every operation is one IEEE operation per lane, the same on every path, so that a lane
// computes exactly what the one-lane path computes for the same constraint: max and min
// are "a > b ? a : b" and "a < b ? a : b" everywhere (SSE's and AVX's maxps and minps are
// exactly that; NEON's vmaxq differs on signed zeros, so it is a compare and select), negation is
// written as a subtraction, and nothing is fused (the library is built with -ffp-contract=off).
// Box2D v3's solver (simd.h and contact_solver.c) showed the shape of this; the code is our own.

#include <cstdint>

#if defined(QUACK_SIMD_AVX2)
#include <immintrin.h>
#elif defined(QUACK_SIMD_SSE2)
#include <emmintrin.h>
#elif defined(QUACK_SIMD_NEON)
#include <arm_neon.h>
#endif

namespace quack::detail {

// The solver's per-body state, gathered a lane per body (32 bytes: one AVX2 row, two SSE2
// or NEON rows). Slot 0 of the solver's array is a body at rest that never moves: static
// bodies and empty lanes read it.
struct alignas(32) BodyState {
  float vx = 0.0f, vy = 0.0f, w = 0.0f, pad = 0.0f;  // pad: unused (scatter writes 0)
  float dpx = 0.0f, dpy = 0.0f;  // displacement of the centre of mass since the step began
  float qc = 1.0f, qs = 0.0f;    // rotation since the step began
};
static_assert(sizeof(BodyState) == 32);

// The 3D solver's per-body state (64 bytes: four rows of four floats, two AVX2 rows). The
// pads are unused (scatter writes 0). Slot 0 is the 3D body at rest, as above.
struct alignas(64) BodyState3 {
  float vx = 0.0f, vy = 0.0f, vz = 0.0f, pad0 = 0.0f;     // linear velocity
  float wx = 0.0f, wy = 0.0f, wz = 0.0f, pad1 = 0.0f;     // angular velocity (world axes)
  float dpx = 0.0f, dpy = 0.0f, dpz = 0.0f, pad2 = 0.0f;  // motion of the centre of mass
  // The turn since the step began as a rotation vector, to first order (twice the vector
  // part of the delta quaternion): the solver turns the anchors by it.
  float tx = 0.0f, ty = 0.0f, tz = 0.0f, pad3 = 0.0f;
};
static_assert(sizeof(BodyState3) == 64);

// ---- one lane -------------------------------------------------------------------------

struct FloatS {
  static constexpr int width = 1;
  float v;
};
struct MaskS {
  bool m;
};
inline FloatS splat(float x, FloatS) {
  return {x};
}
inline FloatS load(const float* p, FloatS) {
  return {*p};
}
inline void store(float* p, FloatS a) {
  *p = a.v;
}
inline FloatS operator+(FloatS a, FloatS b) {
  return {a.v + b.v};
}
inline FloatS operator-(FloatS a, FloatS b) {
  return {a.v - b.v};
}
inline FloatS operator*(FloatS a, FloatS b) {
  return {a.v * b.v};
}
inline FloatS maxW(FloatS a, FloatS b) {
  return {a.v > b.v ? a.v : b.v};
}
inline FloatS minW(FloatS a, FloatS b) {
  return {a.v < b.v ? a.v : b.v};
}
inline MaskS greater(FloatS a, FloatS b) {
  return {a.v > b.v};
}
inline MaskS operator&(MaskS a, MaskS b) {
  return {a.m && b.m};
}
inline FloatS select(MaskS m, FloatS a, FloatS b) {
  return {m.m ? a.v : b.v};
}
inline bool any(MaskS m) {
  return m.m;
}

// Lanes of body state: velocities (written back) and the motion since the step began.
template <class F>
struct BodyLanes {
  F vx, vy, w, pad, dpx, dpy, qc, qs;
};

inline BodyLanes<FloatS> gather(const BodyState* states, const std::int32_t* slots, FloatS) {
  const BodyState& s = states[slots[0]];
  return {{s.vx}, {s.vy}, {s.w}, {s.pad}, {s.dpx}, {s.dpy}, {s.qc}, {s.qs}};
}
[[gnu::always_inline]] inline void scatter(BodyState* states, const std::int32_t* slots,
                                           std::uint32_t writeMask, const BodyLanes<FloatS>& b) {
  if ((writeMask & 1u) == 0) return;
  BodyState& s = states[slots[0]];
  s.vx = b.vx.v;
  s.vy = b.vy.v;
  s.w = b.w.v;
}

inline FloatS operator/(FloatS a, FloatS b) {
  return {a.v / b.v};
}
inline FloatS sqrtW(FloatS a) {
  return {__builtin_sqrtf(a.v)};
}

// Lanes of 3D body state.
template <class F>
struct BodyLanes3 {
  F vx, vy, vz, wx, wy, wz, dpx, dpy, dpz, tx, ty, tz;
};

inline BodyLanes3<FloatS> gather3(const BodyState3* states, const std::int32_t* slots, FloatS) {
  const BodyState3& s = states[slots[0]];
  return {{s.vx},  {s.vy},  {s.vz},  {s.wx}, {s.wy}, {s.wz},
          {s.dpx}, {s.dpy}, {s.dpz}, {s.tx}, {s.ty}, {s.tz}};
}
inline void scatter3(BodyState3* states, const std::int32_t* slots, std::uint32_t writeMask,
                     const BodyLanes3<FloatS>& b) {
  if ((writeMask & 1u) == 0) return;
  BodyState3& s = states[slots[0]];
  s.vx = b.vx.v;
  s.vy = b.vy.v;
  s.vz = b.vz.v;
  s.wx = b.wx.v;
  s.wy = b.wy.v;
  s.wz = b.wz.v;
}

// ---- the build's SIMD lanes ---------------------------------------------------------------

#if defined(QUACK_SIMD_AVX2)

inline constexpr const char* kSimdPath = "avx2";
struct FloatW {
  static constexpr int width = 8;
  __m256 v;
};
struct MaskW {
  __m256 m;
};
inline FloatW splat(float x, FloatW) {
  return {_mm256_set1_ps(x)};
}
inline FloatW load(const float* p, FloatW) {
  return {_mm256_load_ps(p)};
}
inline void store(float* p, FloatW a) {
  _mm256_store_ps(p, a.v);
}
inline FloatW operator+(FloatW a, FloatW b) {
  return {_mm256_add_ps(a.v, b.v)};
}
inline FloatW operator-(FloatW a, FloatW b) {
  return {_mm256_sub_ps(a.v, b.v)};
}
inline FloatW operator*(FloatW a, FloatW b) {
  return {_mm256_mul_ps(a.v, b.v)};
}
// vmaxps returns its second operand unless the first is greater (equal, both zeros of
// either sign, or a NaN): exactly "a > b ? a : b". vminps likewise "a < b ? a : b".
inline FloatW maxW(FloatW a, FloatW b) {
  return {_mm256_max_ps(a.v, b.v)};
}
inline FloatW minW(FloatW a, FloatW b) {
  return {_mm256_min_ps(a.v, b.v)};
}
inline MaskW greater(FloatW a, FloatW b) {
  return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)};
}
inline MaskW operator&(MaskW a, MaskW b) {
  return {_mm256_and_ps(a.m, b.m)};
}
inline FloatW select(MaskW m, FloatW a, FloatW b) {
  return {_mm256_blendv_ps(b.v, a.v, m.m)};
}
inline bool any(MaskW m) {
  return _mm256_movemask_ps(m.m) != 0;
}

// Eight rows of eight floats to eight columns (the usual unpack, shuffle, permute).
inline void transpose8(__m256 r[8]) {
  __m256 t[8], u[8];
  for (int i = 0; i < 4; ++i) {
    t[2 * i] = _mm256_unpacklo_ps(r[2 * i], r[2 * i + 1]);
    t[2 * i + 1] = _mm256_unpackhi_ps(r[2 * i], r[2 * i + 1]);
  }
  for (int i = 0; i < 2; ++i) {
    u[4 * i + 0] = _mm256_shuffle_ps(t[4 * i], t[4 * i + 2], _MM_SHUFFLE(1, 0, 1, 0));
    u[4 * i + 1] = _mm256_shuffle_ps(t[4 * i], t[4 * i + 2], _MM_SHUFFLE(3, 2, 3, 2));
    u[4 * i + 2] = _mm256_shuffle_ps(t[4 * i + 1], t[4 * i + 3], _MM_SHUFFLE(1, 0, 1, 0));
    u[4 * i + 3] = _mm256_shuffle_ps(t[4 * i + 1], t[4 * i + 3], _MM_SHUFFLE(3, 2, 3, 2));
  }
  for (int i = 0; i < 4; ++i) {
    r[i] = _mm256_permute2f128_ps(u[i], u[i + 4], 0x20);
    r[i + 4] = _mm256_permute2f128_ps(u[i], u[i + 4], 0x31);
  }
}

[[gnu::always_inline]] inline BodyLanes<FloatW> gather(const BodyState* states,
                                                       const std::int32_t* slots, FloatW) {
  __m256 r[8];
  for (int i = 0; i < 8; ++i)
    r[i] = _mm256_load_ps(&states[slots[i]].vx);
  transpose8(r);
  return {{r[0]}, {r[1]}, {r[2]}, {r[3]}, {r[4]}, {r[5]}, {r[6]}, {r[7]}};
}
// Writes the velocities back: vx, vy, w and a zero pad (unused) per body, 16 bytes each.
[[gnu::always_inline]] inline void scatter(BodyState* states, const std::int32_t* slots,
                                           std::uint32_t writeMask, const BodyLanes<FloatW>& b) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256 t0 = _mm256_unpacklo_ps(b.vx.v, b.vy.v), t1 = _mm256_unpackhi_ps(b.vx.v, b.vy.v);
  const __m256 t2 = _mm256_unpacklo_ps(b.w.v, zero), t3 = _mm256_unpackhi_ps(b.w.v, zero);
  const __m256 u[4] = {_mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)),
                       _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2)),
                       _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)),
                       _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2))};
  for (int i = 0; i < 4; ++i) {
    if ((writeMask >> i) & 1u) _mm_store_ps(&states[slots[i]].vx, _mm256_castps256_ps128(u[i]));
    if ((writeMask >> (i + 4)) & 1u)
      _mm_store_ps(&states[slots[i + 4]].vx, _mm256_extractf128_ps(u[i], 1));
  }
}

inline FloatW operator/(FloatW a, FloatW b) {
  return {_mm256_div_ps(a.v, b.v)};
}
inline FloatW sqrtW(FloatW a) {
  return {_mm256_sqrt_ps(a.v)};
}
// Eight bodies: rows 0-1 (v, w) and rows 2-3 (dp, turn) are one 256-bit load each, turned
// to lanes by the 8 x 8 transpose.
inline BodyLanes3<FloatW> gather3(const BodyState3* states, const std::int32_t* slots, FloatW) {
  __m256 r[8], u[8];
  for (int i = 0; i < 8; ++i) {
    r[i] = _mm256_load_ps(&states[slots[i]].vx);
    u[i] = _mm256_load_ps(&states[slots[i]].dpx);
  }
  transpose8(r);
  transpose8(u);
  return {{r[0]}, {r[1]}, {r[2]}, {r[4]}, {r[5]}, {r[6]},
          {u[0]}, {u[1]}, {u[2]}, {u[4]}, {u[5]}, {u[6]}};
}
inline void scatter3(BodyState3* states, const std::int32_t* slots, std::uint32_t writeMask,
                     const BodyLanes3<FloatW>& b) {
  const __m256 zero = _mm256_setzero_ps();
  __m256 r[8] = {b.vx.v, b.vy.v, b.vz.v, zero, b.wx.v, b.wy.v, b.wz.v, zero};
  transpose8(r);
  for (int i = 0; i < 8; ++i)
    if ((writeMask >> i) & 1u) _mm256_store_ps(&states[slots[i]].vx, r[i]);
}

#elif defined(QUACK_SIMD_SSE2)

inline constexpr const char* kSimdPath = "sse2";
struct FloatW {
  static constexpr int width = 4;
  __m128 v;
};
struct MaskW {
  __m128 m;
};
inline FloatW splat(float x, FloatW) {
  return {_mm_set1_ps(x)};
}
inline FloatW load(const float* p, FloatW) {
  return {_mm_load_ps(p)};
}
inline void store(float* p, FloatW a) {
  _mm_store_ps(p, a.v);
}
inline FloatW operator+(FloatW a, FloatW b) {
  return {_mm_add_ps(a.v, b.v)};
}
inline FloatW operator-(FloatW a, FloatW b) {
  return {_mm_sub_ps(a.v, b.v)};
}
inline FloatW operator*(FloatW a, FloatW b) {
  return {_mm_mul_ps(a.v, b.v)};
}
inline FloatW select(MaskW m, FloatW a, FloatW b) {
  return {_mm_or_ps(_mm_and_ps(m.m, a.v), _mm_andnot_ps(m.m, b.v))};
}
inline MaskW greater(FloatW a, FloatW b) {
  return {_mm_cmpgt_ps(a.v, b.v)};
}
// maxps returns its second operand unless the first is greater (equal, both zeros of
// either sign, or a NaN): exactly "a > b ? a : b". minps likewise "a < b ? a : b".
inline FloatW maxW(FloatW a, FloatW b) {
  return {_mm_max_ps(a.v, b.v)};
}
inline FloatW minW(FloatW a, FloatW b) {
  return {_mm_min_ps(a.v, b.v)};
}
inline MaskW operator&(MaskW a, MaskW b) {
  return {_mm_and_ps(a.m, b.m)};
}
inline bool any(MaskW m) {
  return _mm_movemask_ps(m.m) != 0;
}

[[gnu::always_inline]] inline BodyLanes<FloatW> gather(const BodyState* states,
                                                       const std::int32_t* slots, FloatW) {
  __m128 a0 = _mm_load_ps(&states[slots[0]].vx), b0 = _mm_load_ps(&states[slots[0]].dpx);
  __m128 a1 = _mm_load_ps(&states[slots[1]].vx), b1 = _mm_load_ps(&states[slots[1]].dpx);
  __m128 a2 = _mm_load_ps(&states[slots[2]].vx), b2 = _mm_load_ps(&states[slots[2]].dpx);
  __m128 a3 = _mm_load_ps(&states[slots[3]].vx), b3 = _mm_load_ps(&states[slots[3]].dpx);
  _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
  _MM_TRANSPOSE4_PS(b0, b1, b2, b3);
  return {{a0}, {a1}, {a2}, {a3}, {b0}, {b1}, {b2}, {b3}};
}
[[gnu::always_inline]] inline void scatter(BodyState* states, const std::int32_t* slots,
                                           std::uint32_t writeMask, const BodyLanes<FloatW>& b) {
  __m128 r0 = b.vx.v, r1 = b.vy.v, r2 = b.w.v, r3 = _mm_setzero_ps();  // pad: unused
  _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
  if (writeMask & 1u) _mm_store_ps(&states[slots[0]].vx, r0);
  if (writeMask & 2u) _mm_store_ps(&states[slots[1]].vx, r1);
  if (writeMask & 4u) _mm_store_ps(&states[slots[2]].vx, r2);
  if (writeMask & 8u) _mm_store_ps(&states[slots[3]].vx, r3);
}

inline FloatW operator/(FloatW a, FloatW b) {
  return {_mm_div_ps(a.v, b.v)};
}
inline FloatW sqrtW(FloatW a) {
  return {_mm_sqrt_ps(a.v)};
}
// Four bodies: each of the four rows turned to lanes by a 4 x 4 transpose.
inline BodyLanes3<FloatW> gather3(const BodyState3* states, const std::int32_t* slots, FloatW) {
  const float* p[4] = {&states[slots[0]].vx, &states[slots[1]].vx, &states[slots[2]].vx,
                       &states[slots[3]].vx};
  __m128 r[4][4];
  for (int row = 0; row < 4; ++row) {
    for (int i = 0; i < 4; ++i)
      r[row][i] = _mm_load_ps(p[i] + 4 * row);
    _MM_TRANSPOSE4_PS(r[row][0], r[row][1], r[row][2], r[row][3]);
  }
  return {{r[0][0]}, {r[0][1]}, {r[0][2]}, {r[1][0]}, {r[1][1]}, {r[1][2]},
          {r[2][0]}, {r[2][1]}, {r[2][2]}, {r[3][0]}, {r[3][1]}, {r[3][2]}};
}
inline void scatter3(BodyState3* states, const std::int32_t* slots, std::uint32_t writeMask,
                     const BodyLanes3<FloatW>& b) {
  __m128 v0 = b.vx.v, v1 = b.vy.v, v2 = b.vz.v, v3 = _mm_setzero_ps();
  __m128 w0 = b.wx.v, w1 = b.wy.v, w2 = b.wz.v, w3 = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(v0, v1, v2, v3);
  _MM_TRANSPOSE4_PS(w0, w1, w2, w3);
  const __m128 v[4] = {v0, v1, v2, v3}, w[4] = {w0, w1, w2, w3};
  for (int i = 0; i < 4; ++i) {
    if (((writeMask >> i) & 1u) == 0) continue;
    _mm_store_ps(&states[slots[i]].vx, v[i]);
    _mm_store_ps(&states[slots[i]].wx, w[i]);
  }
}

#elif defined(QUACK_SIMD_NEON)

inline constexpr const char* kSimdPath = "neon";
struct FloatW {
  static constexpr int width = 4;
  float32x4_t v;
};
struct MaskW {
  uint32x4_t m;
};
inline FloatW splat(float x, FloatW) {
  return {vdupq_n_f32(x)};
}
inline FloatW load(const float* p, FloatW) {
  return {vld1q_f32(p)};
}
inline void store(float* p, FloatW a) {
  vst1q_f32(p, a.v);
}
inline FloatW operator+(FloatW a, FloatW b) {
  return {vaddq_f32(a.v, b.v)};
}
inline FloatW operator-(FloatW a, FloatW b) {
  return {vsubq_f32(a.v, b.v)};
}
inline FloatW operator*(FloatW a, FloatW b) {
  return {vmulq_f32(a.v, b.v)};
}
inline FloatW select(MaskW m, FloatW a, FloatW b) {
  return {vbslq_f32(m.m, a.v, b.v)};
}
inline MaskW greater(FloatW a, FloatW b) {
  return {vcgtq_f32(a.v, b.v)};
}
inline FloatW maxW(FloatW a, FloatW b) {
  return select(greater(a, b), a, b);
}
inline FloatW minW(FloatW a, FloatW b) {
  return select({vcltq_f32(a.v, b.v)}, a, b);
}
inline MaskW operator&(MaskW a, MaskW b) {
  return {vandq_u32(a.m, b.m)};
}
inline bool any(MaskW m) {
  return vmaxvq_u32(m.m) != 0;
}

// Four rows to four columns with two rounds of zips.
inline void transpose4(float32x4_t& r0, float32x4_t& r1, float32x4_t& r2, float32x4_t& r3) {
  float32x4x2_t p = vzipq_f32(r0, r2), q = vzipq_f32(r1, r3);
  float32x4x2_t c01 = vzipq_f32(p.val[0], q.val[0]), c23 = vzipq_f32(p.val[1], q.val[1]);
  r0 = c01.val[0];
  r1 = c01.val[1];
  r2 = c23.val[0];
  r3 = c23.val[1];
}
[[gnu::always_inline]] inline BodyLanes<FloatW> gather(const BodyState* states,
                                                       const std::int32_t* slots, FloatW) {
  float32x4_t a0 = vld1q_f32(&states[slots[0]].vx), b0 = vld1q_f32(&states[slots[0]].dpx);
  float32x4_t a1 = vld1q_f32(&states[slots[1]].vx), b1 = vld1q_f32(&states[slots[1]].dpx);
  float32x4_t a2 = vld1q_f32(&states[slots[2]].vx), b2 = vld1q_f32(&states[slots[2]].dpx);
  float32x4_t a3 = vld1q_f32(&states[slots[3]].vx), b3 = vld1q_f32(&states[slots[3]].dpx);
  transpose4(a0, a1, a2, a3);
  transpose4(b0, b1, b2, b3);
  return {{a0}, {a1}, {a2}, {a3}, {b0}, {b1}, {b2}, {b3}};
}
[[gnu::always_inline]] inline void scatter(BodyState* states, const std::int32_t* slots,
                                           std::uint32_t writeMask, const BodyLanes<FloatW>& b) {
  float32x4_t r0 = b.vx.v, r1 = b.vy.v, r2 = b.w.v, r3 = vdupq_n_f32(0.0f);  // pad: unused
  transpose4(r0, r1, r2, r3);
  if (writeMask & 1u) vst1q_f32(&states[slots[0]].vx, r0);
  if (writeMask & 2u) vst1q_f32(&states[slots[1]].vx, r1);
  if (writeMask & 4u) vst1q_f32(&states[slots[2]].vx, r2);
  if (writeMask & 8u) vst1q_f32(&states[slots[3]].vx, r3);
}

inline FloatW operator/(FloatW a, FloatW b) {
  return {vdivq_f32(a.v, b.v)};
}
inline FloatW sqrtW(FloatW a) {
  return {vsqrtq_f32(a.v)};
}
// Four bodies: each of the four rows turned to lanes by a 4 x 4 transpose.
inline BodyLanes3<FloatW> gather3(const BodyState3* states, const std::int32_t* slots, FloatW) {
  const float* p[4] = {&states[slots[0]].vx, &states[slots[1]].vx, &states[slots[2]].vx,
                       &states[slots[3]].vx};
  float32x4_t r[4][4];
  for (int row = 0; row < 4; ++row) {
    for (int i = 0; i < 4; ++i)
      r[row][i] = vld1q_f32(p[i] + 4 * row);
    transpose4(r[row][0], r[row][1], r[row][2], r[row][3]);
  }
  return {{r[0][0]}, {r[0][1]}, {r[0][2]}, {r[1][0]}, {r[1][1]}, {r[1][2]},
          {r[2][0]}, {r[2][1]}, {r[2][2]}, {r[3][0]}, {r[3][1]}, {r[3][2]}};
}
inline void scatter3(BodyState3* states, const std::int32_t* slots, std::uint32_t writeMask,
                     const BodyLanes3<FloatW>& b) {
  float32x4_t v0 = b.vx.v, v1 = b.vy.v, v2 = b.vz.v, v3 = vdupq_n_f32(0.0f);
  float32x4_t w0 = b.wx.v, w1 = b.wy.v, w2 = b.wz.v, w3 = vdupq_n_f32(0.0f);
  transpose4(v0, v1, v2, v3);
  transpose4(w0, w1, w2, w3);
  const float32x4_t v[4] = {v0, v1, v2, v3}, w[4] = {w0, w1, w2, w3};
  for (int i = 0; i < 4; ++i) {
    if (((writeMask >> i) & 1u) == 0) continue;
    vst1q_f32(&states[slots[i]].vx, v[i]);
    vst1q_f32(&states[slots[i]].wx, w[i]);
  }
}

#else

inline constexpr const char* kSimdPath = "scalar";
using FloatW = FloatS;
using MaskW = MaskS;

#endif

// The solvers' shorthands for any lane type F: a load, a splat.
template <class F>
F ld(const float* p) {
  return load(p, F{});
}
template <class F>
F sp(float x) {
  return splat(x, F{});
}

// An impulse P at the arms rA, rB of each lane: -P on A, +P on B (the contacts' and the
// revolute joints' lanes share it).
template <class F>
void applyImpulse(BodyLanes<F>& A, BodyLanes<F>& B, F mA, F iA, F mB, F iB, F rAx, F rAy, F rBx,
                  F rBy, F Px, F Py) {
  A.vx = A.vx - mA * Px;
  A.vy = A.vy - mA * Py;
  A.w = A.w - iA * (rAx * Py - rAy * Px);
  B.vx = B.vx + mB * Px;
  B.vy = B.vy + mB * Py;
  B.w = B.w + iB * (rBx * Py - rBy * Px);
}

}  // namespace quack::detail
