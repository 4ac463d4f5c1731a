// Quat, Mat3 and Transform3: hand-worked rotations, the algebra (composition, inverse,
// matrix agreement) against double-precision references, and random poses.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "quack/math/transform3.hpp"

namespace quack {
namespace {

static_assert(rotate(Quat{}, Vec3{1, 2, 3}) == Vec3{1, 2, 3});
static_assert(determinant(Mat3::identity()) == 1.0f);
static_assert(Mat3::identity() * Vec3{1, 2, 3} == Vec3{1, 2, 3});
static_assert(transformPoint(Transform3{{1, 2, 3}, {}}, Vec3{1, 1, 1}) == Vec3{2, 3, 4});

void expectNear(Vec3 a, Vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}
void expectNear(Mat3 a, Mat3 b, float tol) {
  expectNear(a.cx, b.cx, tol);
  expectNear(a.cy, b.cy, tol);
  expectNear(a.cz, b.cz, tol);
}

Quat randomQuat(std::mt19937& rng) {
  std::normal_distribution<float> n(0, 1);
  return normalize(Quat{n(rng), n(rng), n(rng), n(rng)});
}

TEST(Quat, QuarterTurnsAreRightHanded) {
  // +90 degrees about z takes x to y; about x takes y to z; about y takes z to x.
  expectNear(rotate(Quat::fromAxisAngle({0, 0, 1}, 0.5f * kPi), {1, 0, 0}), {0, 1, 0}, 1e-6f);
  expectNear(rotate(Quat::fromAxisAngle({1, 0, 0}, 0.5f * kPi), {0, 1, 0}), {0, 0, 1}, 1e-6f);
  expectNear(rotate(Quat::fromAxisAngle({0, 1, 0}, 0.5f * kPi), {0, 0, 1}), {1, 0, 0}, 1e-6f);
  Quat q = Quat::fromAxisAngle({0, 0, 1}, 0.5f * kPi);
  EXPECT_NEAR(q.w, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(q.z, std::sqrt(0.5f), 1e-6f);
}

TEST(Quat, ProductComposesAndConjugateInverts) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-10, 10);
  for (int i = 0; i < 1000; ++i) {
    Quat a = randomQuat(rng), b = randomQuat(rng);
    Vec3 v{u(rng), u(rng), u(rng)};
    expectNear(rotate(a * b, v), rotate(a, rotate(b, v)), 2e-5f);
    expectNear(invRotate(a, rotate(a, v)), v, 2e-5f);
    expectNear(rotate(invMul(a, b), v), invRotate(a, rotate(b, v)), 2e-5f);
    EXPECT_NEAR(lengthSquared(a * b), 1.0f, 1e-5f);
    // Rotation keeps lengths and the handedness of cross products.
    Vec3 w{u(rng), u(rng), u(rng)};
    EXPECT_NEAR(length(rotate(a, v)), length(v), 1e-4f);
    expectNear(rotate(a, cross(v, w)), cross(rotate(a, v), rotate(a, w)), 1e-3f);
  }
}

TEST(Quat, MatrixAgreesWithRotateAndIsOrthonormal) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-10, 10);
  for (int i = 0; i < 1000; ++i) {
    Quat q = randomQuat(rng);
    Mat3 m = toMat3(q);
    Vec3 v{u(rng), u(rng), u(rng)};
    expectNear(m * v, rotate(q, v), 2e-5f);
    expectNear(transpose(m) * m, Mat3::identity(), 1e-5f);
    EXPECT_NEAR(determinant(m), 1.0f, 1e-5f);
    expectNear(toMat3(Quat{-q.x, -q.y, -q.z, -q.w}), m, 1e-6f);  // q and -q agree
  }
}

TEST(Quat, AxisAngleAgreesWithRodrigues) {
  // Rodrigues' formula in double: v cos a + (k x v) sin a + k (k.v)(1 - cos a).
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1), ang(-10, 10);
  for (int i = 0; i < 1000; ++i) {
    Vec3 k = normalize(Vec3{u(rng), u(rng), u(rng)});
    if (lengthSquared(k) == 0.0f) continue;
    float a = ang(rng);
    Vec3 v{u(rng), u(rng), u(rng)};
    double c = std::cos(double(a)), s = std::sin(double(a));
    double kv = double(k.x) * v.x + double(k.y) * v.y + double(k.z) * v.z;
    Vec3 kxv = cross(k, v);
    Vec3 ref{float(v.x * c + kxv.x * s + k.x * kv * (1 - c)),
             float(v.y * c + kxv.y * s + k.y * kv * (1 - c)),
             float(v.z * c + kxv.z * s + k.z * kv * (1 - c))};
    expectNear(rotate(Quat::fromAxisAngle(k, a), v), ref, 1e-5f);
  }
}

TEST(Quat, NormaliseRestoresUnitAndZeroIsIdentity) {
  Quat q = normalize(Quat{0, 0, 3, 4});
  EXPECT_NEAR(q.z, 0.6f, 1e-7f);
  EXPECT_NEAR(q.w, 0.8f, 1e-7f);
  EXPECT_EQ(normalize(Quat{0, 0, 0, 0}), Quat{});
  EXPECT_FALSE(isFinite(Quat{NAN, 0, 0, 1}));
}

TEST(Quat, IntegrateRotationMatchesAxisAngleForSmallSteps) {
  Vec3 omega{0, 0, 2};  // 2 rad/s about z
  Quat q{};
  for (int i = 0; i < 100; ++i)
    q = integrateRotation(q, omega, 0.001f);
  Quat ref = Quat::fromAxisAngle({0, 0, 1}, 0.2f);
  EXPECT_NEAR(std::fabs(dot(q, ref)), 1.0f, 1e-5f);
}

TEST(Mat3, InverseDeterminantTransposeByHand) {
  Mat3 m = Mat3::fromRows({2, 0, 0}, {0, 3, 0}, {1, 0, 4});
  EXPECT_FLOAT_EQ(determinant(m), 24.0f);
  expectNear(m * Vec3{1, 1, 1}, {2, 3, 5}, 0);
  expectNear(mulTranspose(m, Vec3{1, 1, 1}), transpose(m) * Vec3{1, 1, 1}, 0);
  expectNear(inverse(m) * m, Mat3::identity(), 1e-6f);
  expectNear(m * inverse(m), Mat3::identity(), 1e-6f);
  EXPECT_EQ(inverse(Mat3::fromRows({1, 2, 3}, {2, 4, 6}, {0, 0, 1})), Mat3{});  // singular
  expectNear(skew(Vec3{1, 2, 3}) * Vec3{4, 5, 6}, cross(Vec3{1, 2, 3}, Vec3{4, 5, 6}), 0);
  expectNear(outer({1, 2, 3}, {1, 0, 0}) * Vec3{2, 7, 7}, {2, 4, 6}, 0);
  EXPECT_EQ(trace(m), 9.0f);
}

TEST(Mat3, RandomInverseAndProduct) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  int checked = 0;
  for (int i = 0; i < 1000; ++i) {
    Mat3 a{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    Mat3 b{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    Vec3 v{u(rng), u(rng), u(rng)};
    expectNear((a * b) * v, a * (b * v), 1e-5f);
    EXPECT_NEAR(determinant(a * b), determinant(a) * determinant(b), 1e-4f);
    EXPECT_NEAR(determinant(transpose(a)), determinant(a), 1e-5f);
    if (std::fabs(determinant(a)) < 0.05f) continue;  // keep the condition number modest
    expectNear(a * (inverse(a) * v), v, 1e-3f);
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

TEST(Transform3, CompositionInverseAndInvMulAgree) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> pos(-100, 100);
  for (int i = 0; i < 1000; ++i) {
    Transform3 aFromB{{pos(rng), pos(rng), pos(rng)}, randomQuat(rng)};
    Transform3 bFromC{{pos(rng), pos(rng), pos(rng)}, randomQuat(rng)};
    Vec3 pC{pos(rng), pos(rng), pos(rng)};
    Transform3 aFromC = aFromB * bFromC;
    expectNear(transformPoint(aFromC, pC), transformPoint(aFromB, transformPoint(bFromC, pC)),
               1e-3f);
    expectNear(transformPoint(inverse(aFromB), transformPoint(aFromB, pC)), pC, 1e-3f);
    expectNear(invTransformPoint(aFromB, transformPoint(aFromB, pC)), pC, 1e-3f);
    Transform3 viaInvMul = invMul(aFromB, aFromC);
    expectNear(transformPoint(viaInvMul, pC), transformPoint(bFromC, pC), 2e-3f);
    expectNear(invTransformVector(aFromB, transformVector(aFromB, pC)), pC, 1e-3f);
  }
}

TEST(Transform3, WorldFromBodyByHand) {
  Transform3 worldFromBody = makeTransform3({10, 0, 0}, Quat::fromAxisAngle({0, 1, 0}, 0.5f * kPi));
  expectNear(transformPoint(worldFromBody, {0, 0, 1}), {11, 0, 0}, 1e-6f);
  expectNear(invTransformPoint(worldFromBody, {11, 0, 0}), {0, 0, 1}, 1e-6f);
  expectNear(transformVector(worldFromBody, {0, 0, 1}), {1, 0, 0}, 1e-6f);
  Transform3 t = makeTransform3({}, Quat{0, 0, 0, 2});  // normalised on the way in
  EXPECT_EQ(t.q, Quat{});
}

}  // namespace
}  // namespace quack
