// Mass properties of primitives and compounds against analytic formulas.
// Tolerance: 1e-5 relative (float rounding of closed-form expressions).
#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "fulcrum/shape.hpp"
#include "test_util.hpp"

namespace fulcrum {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRel = 1e-5;

void expectDiagonal(const Mat3& m, double x, double y, double z) {
    const double scale = std::max({x, y, z});
    EXPECT_NEAR(m(0, 0), x, kRel * scale);
    EXPECT_NEAR(m(1, 1), y, kRel * scale);
    EXPECT_NEAR(m(2, 2), z, kRel * scale);
    EXPECT_NEAR(m(0, 1), 0, kRel * scale);
    EXPECT_NEAR(m(0, 2), 0, kRel * scale);
    EXPECT_NEAR(m(1, 2), 0, kRel * scale);
}

TEST(MassProperties, Sphere) {
    const double r = 0.7, rho = 1200, m = rho * 4.0 / 3.0 * kPi * r * r * r;
    const MassProperties mp = Shape::sphere(Real(r)).massProperties(Real(rho));
    EXPECT_NEAR(mp.mass, m, kRel * m);
    expectDiagonal(mp.inertia, 0.4 * m * r * r, 0.4 * m * r * r, 0.4 * m * r * r);
}

TEST(MassProperties, Box) {
    // Full dimensions a, b, c: I_x = m (b^2 + c^2) / 12.
    const double a = 2, b = 0.6, c = 1.4, rho = 3, m = rho * a * b * c;
    const MassProperties mp = Shape::box({Real(a / 2), Real(b / 2), Real(c / 2)}).massProperties(Real(rho));
    EXPECT_NEAR(mp.mass, m, kRel * m);
    expectDiagonal(mp.inertia, m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12);
}

TEST(MassProperties, CapsuleFromItsPieces) {
    // A cylinder of length 2h plus two hemispheres; each hemisphere has
    // I = 83/320 m r^2 about its own centroid (transverse), which sits
    // h + 3r/8 from the capsule's centre.
    const double r = 0.3, h = 0.8, rho = 500;
    const double mc = rho * kPi * r * r * 2 * h, mh = rho * 2.0 / 3.0 * kPi * r * r * r;
    const double iy = mc * r * r / 2 + 2 * (0.4 * mh * r * r);
    const double d = h + 3 * r / 8;
    const double ix = mc * (3 * r * r + 4 * h * h) / 12 + 2 * (83.0 / 320.0 * mh * r * r + mh * d * d);
    const Shape s = Shape::capsule(Real(r), Real(h));
    const MassProperties mp = s.massProperties(Real(rho));
    EXPECT_NEAR(mp.mass, mc + 2 * mh, kRel * (mc + 2 * mh));
    EXPECT_NEAR(s.volume(), (mc + 2 * mh) / rho, kRel * (mc + 2 * mh) / rho);
    expectDiagonal(mp.inertia, ix, iy, ix);
}

TEST(MassProperties, Cylinder) {
    // I = m (3 r^2 + H^2) / 12 transverse (H the full height), m r^2 / 2 about the axis.
    const double r = 0.5, h = 1.1, rho = 7, m = rho * kPi * r * r * 2 * h;
    const MassProperties mp = Shape::cylinder(Real(r), Real(h)).massProperties(Real(rho));
    EXPECT_NEAR(mp.mass, m, kRel * m);
    const double ix = m * (3 * r * r + 4 * h * h) / 12;
    expectDiagonal(mp.inertia, ix, m * r * r / 2, ix);
}

TEST(MassProperties, CompoundDumbbell) {
    // Two spheres of mass m at x = +-d: I_x = 2 (2/5 m r^2), I_y = I_z = 2 (2/5 m r^2 + m d^2).
    const double r = 0.25, d = 1.5, rho = 2, m = rho * 4.0 / 3.0 * kPi * r * r * r;
    const std::vector<CompoundChild> children{{Shape::sphere(Real(r)), Transform({Real(d), 0, 0}, Quat::identity())},
                                              {Shape::sphere(Real(r)), Transform({Real(-d), 0, 0}, Quat::identity())}};
    const MassProperties mp = Shape::compound(children).massProperties(Real(rho));
    EXPECT_NEAR(mp.mass, 2 * m, kRel * m);
    EXPECT_NEAR(length(mp.centerOfMass), 0, 1e-6);
    const double is = 0.4 * m * r * r;
    expectDiagonal(mp.inertia, 2 * is, 2 * (is + m * d * d), 2 * (is + m * d * d));
}

TEST(MassProperties, BoxSplitIntoTwoHalvesEqualsTheBox) {
    const Vec3 h{1, Real(0.4), Real(0.7)};
    const Vec3 offset{Real(0.3), -1, 2};  // the compound's origin away from the centre of mass
    const std::vector<CompoundChild> halves{
        {Shape::box({h.x / 2, h.y, h.z}), Transform(offset + Vec3{h.x / 2, 0, 0}, Quat::identity())},
        {Shape::box({h.x / 2, h.y, h.z}), Transform(offset - Vec3{h.x / 2, 0, 0}, Quat::identity())}};
    const MassProperties split = Shape::compound(halves).massProperties(3);
    const MassProperties whole = Shape::box(h).massProperties(3);
    EXPECT_NEAR(split.mass, whole.mass, kRel * whole.mass);
    EXPECT_LT(length(split.centerOfMass - offset), 1e-5);
    EXPECT_LT(test::maxAbsDiff(split.inertia, whole.inertia), kRel * whole.inertia(1, 1));
}

TEST(MassProperties, RotatedChildRotatesItsInertia) {
    // A box turned 90 degrees about z is the box with x and y extents swapped.
    const Vec3 h{2, Real(0.5), 1};
    const std::vector<CompoundChild> child{
        {Shape::box(h), Transform({1, 2, 3}, Quat::fromAxisAngle({0, 0, 1}, std::numbers::pi_v<Real> / 2))}};
    const MassProperties rotated = Shape::compound(child).massProperties(1);
    const MassProperties swapped = Shape::box({h.y, h.x, h.z}).massProperties(1);
    EXPECT_LT(length(rotated.centerOfMass - Vec3{1, 2, 3}), 1e-5);
    EXPECT_LT(test::maxAbsDiff(rotated.inertia, swapped.inertia), 1e-5 * swapped.inertia(2, 2));
}

template <class F>
void expectErrorContaining(F&& f, const std::string& fragment) {
    try {
        f();
        ADD_FAILURE() << "expected an error containing '" << fragment << "'";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

TEST(MassProperties, ShapesWithoutVolumeAndEmptyCompoundsAreErrors) {
    expectErrorContaining([] { (void)Shape::compound({}); }, "compound: needs at least one child shape");
    expectErrorContaining([] { (void)Shape::plane({0, 1, 0}, 0).massProperties(1); }, "plane shapes have no volume");
    const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    const std::vector<std::array<std::uint32_t, 3>> t{{0, 2, 1}};
    expectErrorContaining([&] { (void)Shape::mesh(v, t).massProperties(1); }, "mesh shapes have no volume");
    expectErrorContaining([] { (void)Shape::sphere(1).massProperties(-2); }, "density must be a positive finite number");
}

}  // namespace
}  // namespace fulcrum
