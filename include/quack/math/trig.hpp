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
