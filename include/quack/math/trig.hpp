#pragma once
/// Quack's own sine, cosine and arctangents: the same bits on every platform.
///
/// The C library's `sinf`/`cosf`/`atan2f` differ between C libraries (glibc, musl,
/// emscripten's, Apple's) in the last bit, and those bits reach the simulation state through
/// `Rot::fromAngle`, `Rot::angle` and the solver. These functions use only IEEE-754
/// operations that every conforming platform rounds identically (double add, multiply,
/// divide, integer arithmetic), compiled in one translation unit with `-ffp-contract=off`, so
/// g++ and clang, x86-64, aarch64 and WebAssembly give identical results (docs/determinism.md,
/// "Builds").
///
/// Accuracy: the result is the float nearest a double-precision value within a few double
/// ulps of the true one, so it is within 0.5 float ulp plus about 2^-50 relative of the
/// exact value, for every finite float argument (sine and cosine reduce even huge angles
/// exactly, with 2/pi to 224 bits). tests/math/trig_test.cpp measures it against the C
/// library's double functions.
///
/// Special values follow the C standard (Annex F) for `sinf`, `cosf`, `atanf` and `atan2f`:
/// sin(-0) = -0, cos(+-0) = 1, NaN in gives NaN, sin and cos of an infinity give NaN,
/// atan2(+-0, -0) = +-pi, atan2(+-inf, +inf) = +-pi/4, and so on.

namespace quack {

/// Cosine and sine of one angle, from portableCosSin.
struct CosSin {
  float cosine = 1.0f;
  float sine = 0.0f;
};

/// cos(radians) and sin(radians) together, cheaply: the fast path of Rot::fromAngle, where
/// a simulation builds its rotations. For |radians| <= kFastTrigLimit the angle is reduced
/// by a three-part pi/2 (Cody and Waite) in double and both results come from short
/// polynomials in double: each within 1 float ulp of the exact value (within 0.5 ulp plus
/// about 2^-40 relative; tests/math/trig_test.cpp measures it against the C library's double
/// functions), for about a quarter of the instructions of portableCos and portableSin
/// together (docs/determinism.md, "Builds"). Beyond the limit, and for NaN and the
/// infinities, it returns portableCos and portableSin exactly. The same bits on every
/// platform, as the functions below (IEEE double operations only, -ffp-contract=off).
CosSin portableCosSin(float radians) noexcept;

namespace detail {
// portableCosSin as the targets without SSE2 compute it (Horner's rule in scalar doubles),
// on every target: the tests check that the SSE2 form gives the same bits.
CosSin portableCosSinScalar(float radians) noexcept;
}  // namespace detail

/// Where portableCosSin leaves its fast path: 1e5 rad, ten times the angle a scene file may
/// give (1e4 rad); there the three-part reduction is still exact to 2^-70 of a turn.
inline constexpr float kFastTrigLimit = 1.0e5f;

/// sin(radians); any float, see above.
float portableSin(float radians) noexcept;
/// cos(radians); any float.
float portableCos(float radians) noexcept;
/// The angle of (x, y) from the +x axis in [-pi, pi] (pi rounded to the nearest float);
/// atan2(y, x) of the C standard, special values included.
float portableAtan2(float y, float x) noexcept;
/// atan(x) in [-pi/2, pi/2].
float portableAtan(float x) noexcept;

}  // namespace quack
