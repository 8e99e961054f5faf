// The axisymmetric drift runs four bodies at once where it can, then a pair,
// then one alone (one per SIMD lane: src/dynamics/integrators.cpp); the tops
// below (six about y, two about z, one about x) fill a group of four and leave
// the rest to pairs and single bodies. Each lane must do exactly the
// scalar operations: a body's bits may not depend on whether, or with which
// body, it was paired, and every paired body must still follow the closed-form
// torque-free motion of a symmetric top.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "dynamics/test_scenes.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

struct Top {
    Shape shape;
    Vec3 w0;
};

// Capsules and cylinders (symmetry axis y) and boxes with two equal sides
// (symmetry about x or z), tumbling in zero gravity, far apart (no contacts).
std::vector<Top> tops() {
    return {
        {Shape::capsule(Real(0.1), Real(0.4)), {Real(1.5), 5, Real(-0.7)}},
        {Shape::capsule(Real(0.2), Real(0.3)), {Real(-2), Real(0.5), 3}},
        {Shape::cylinder(Real(0.3), Real(0.1)), {Real(0.3), -4, Real(1.1)}},
        {Shape::capsule(Real(0.05), Real(0.5)), {4, Real(-1), Real(0.2)}},
        {Shape::box({Real(0.5), Real(0.2), Real(0.2)}), {Real(2.5), Real(1.5), Real(-1)}},   // symmetric about x
        {Shape::box({Real(0.1), Real(0.1), Real(0.4)}), {Real(-1), 3, Real(2.2)}},           // about z
        {Shape::box({Real(0.3), Real(0.3), Real(0.1)}), {Real(0.7), Real(-0.2), 5}},         // about z
        {Shape::capsule(Real(0.1), Real(0.2)), {}},                                          // at rest: L = 0
        {Shape::capsule(Real(0.1), Real(0.4)), {Real(0.5), 400, Real(0.3)}},                 // beyond the series' range
    };
}

BodyId addTop(World& world, const Top& t, int slot) {
    BodyDef d;
    d.shape = t.shape;
    d.mass = 2;
    d.position = {static_cast<Real>(10 * slot), 0, 0};
    d.angularVelocity = t.w0;
    return world.createBody(d);
}

WorldDef spinning(Integrator integrator) {
    WorldDef def = worldDef(integrator, 2, {0, 0, 0});
    def.maxRotationPerSubstep = std::numeric_limits<Real>::infinity();  // let the fast one go beyond pi/8 per half-step
    return def;
}

bool sameBits(const Quat& a, const Quat& b) { return std::memcmp(&a, &b, sizeof(Quat)) == 0; }
bool sameBits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

}  // namespace

TEST(PairedDrift, EveryBodyHasTheBitsItHasAlone) {
    const std::vector<Top> list = tops();
    for (const Integrator integrator : {Integrator::SemiImplicitEuler, Integrator::Verlet}) {
        World together(spinning(integrator));
        std::vector<BodyId> ids;
        for (std::size_t k = 0; k < list.size(); ++k) ids.push_back(addTop(together, list[k], static_cast<int>(k)));
        for (int i = 0; i < 120; ++i) together.step(Real(1) / 60);
        for (std::size_t k = 0; k < list.size(); ++k) {
            World alone(spinning(integrator));
            const BodyId id = addTop(alone, list[k], static_cast<int>(k));
            for (int i = 0; i < 120; ++i) alone.step(Real(1) / 60);
            EXPECT_TRUE(sameBits(alone.orientation(id), together.orientation(ids[k]))) << "top " << k;
            EXPECT_TRUE(sameBits(alone.angularVelocity(id), together.angularVelocity(ids[k]))) << "top " << k;
        }
    }
}

// Closed form (see RigidRotation.SymmetricTopPrecessesAsTheClosedForm), for
// every paired body: q(t) = rot(L, |L| t / I_t) q0 rot_body(e_a, w0.a (1 - I_a / I_t) t).
TEST(PairedDrift, PairedTopsPrecessAsTheClosedForm) {
    std::vector<Top> list = tops();
    list.resize(7);  // the tumbling ones (the spin limit stays on below)
    World world(worldDef(Integrator::SemiImplicitEuler, 2, {0, 0, 0}));
    std::vector<BodyId> ids;
    for (std::size_t k = 0; k < list.size(); ++k) ids.push_back(addTop(world, list[k], static_cast<int>(k)));
    const double seconds = 10;
    for (int i = 0; i < 600; ++i) world.step(Real(seconds / 600));
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Mat3 inertia = world.localInertia(ids[k]);
        // The symmetry axis: the diagonal entry that differs from the other two.
        int axis = 0;
        if (inertia(0, 0) == inertia(1, 1)) axis = 2;
        else if (inertia(0, 0) == inertia(2, 2)) axis = 1;
        const double ia = inertia(axis, axis), it = inertia((axis + 1) % 3, (axis + 1) % 3);
        Vec3 e{};
        (axis == 0 ? e.x : axis == 1 ? e.y : e.z) = 1;
        const Vec3 w0 = list[k].w0;
        const Vec3 l0 = inertia * w0;  // q0 = identity
        const double precession = length(l0) / it * seconds;
        const double spin = static_cast<double>(dot(w0, e)) * (1 - ia / it) * seconds;
        const Quat expected = Quat::fromAxisAngle(l0, static_cast<Real>(std::fmod(precession, 4 * M_PI))) *
                              Quat::fromAxisAngle(e, static_cast<Real>(std::fmod(spin, 4 * M_PI)));
        const Quat q = world.orientation(ids[k]);
        // Measured: 2e-6 to 3.4e-5 rad (float rounding over 1,200 sub-steps).
        // The angle of q expected^-1 from its vector part, in double (an acos
        // of the dot product resolves only ~1e-3 rad in float).
        const double qw = q.w, qx = q.x, qy = q.y, qz = q.z;
        const double ew = expected.w, ex = -expected.x, ey = -expected.y, ez = -expected.z;
        const double rx = qw * ex + qx * ew + qy * ez - qz * ey;
        const double ry = qw * ey - qx * ez + qy * ew + qz * ex;
        const double rz = qw * ez + qx * ey - qy * ex + qz * ew;
        const double angleError = 2 * std::asin(std::min(1.0, std::sqrt(rx * rx + ry * ry + rz * rz)));
        EXPECT_LT(angleError, 1e-4) << "top " << k << " off the closed form by " << angleError << " rad";
        // L = I_w w is kept.
        const Mat3 r = toMat3(q);
        const Vec3 l = r * inertia * transpose(r) * world.angularVelocity(ids[k]);
        EXPECT_LT(length(l - l0) / length(l0), 1e-4) << "top " << k;
    }
}

// Bodies of general inertia (three distinct moments, or off-diagonal entries:
// a hull) drift four at a time as well (driftGeneralQuad), the rest one by
// one. The list fills one group of four and leaves three alone; the fast one
// is beyond the series' range, so its group goes through the scalar drift.
namespace {

std::vector<Top> tumblers() {
    static const Vec3 rock[] = {{Real(0.4), Real(-0.1), Real(0.2)}, {Real(-0.3), Real(0.2), Real(0.1)},
                                {Real(0.1), Real(0.5), Real(-0.3)}, {Real(-0.2), Real(-0.3), Real(-0.4)},
                                {Real(0.2), Real(0.1), Real(0.45)}};
    return {
        {Shape::box({Real(0.5), Real(0.75), Real(1)}), {Real(1.5), 5, Real(-0.7)}},
        {Shape::box({Real(0.1), Real(0.3), Real(0.2)}), {Real(-2), Real(0.5), 3}},
        {Shape::convexHull(rock), {Real(0.3), -4, Real(1.1)}},
        {Shape::box({Real(0.2), Real(0.4), Real(0.1)}), {4, Real(-1), Real(0.2)}},
        {Shape::box({Real(0.3), Real(0.2), Real(0.6)}), {Real(2.5), Real(1.5), Real(-1)}},
        {Shape::box({Real(0.5), Real(0.75), Real(1)}), {}},                             // at rest
        {Shape::box({Real(0.3), Real(0.1), Real(0.2)}), {Real(0.5), 400, Real(0.3)}},  // beyond the series' range
    };
}

}  // namespace

TEST(PairedDrift, GeneralInertiaBodiesHaveTheBitsTheyHaveAlone) {
    for (const bool withFast : {false, true}) {
        std::vector<Top> list = tumblers();
        if (!withFast) list.pop_back();  // then the first four drift as one group of lanes
        for (const Integrator integrator : {Integrator::SemiImplicitEuler, Integrator::Verlet}) {
            World together(spinning(integrator));
            std::vector<BodyId> ids;
            for (std::size_t k = 0; k < list.size(); ++k) ids.push_back(addTop(together, list[k], static_cast<int>(k)));
            for (int i = 0; i < 120; ++i) together.step(Real(1) / 60);
            for (std::size_t k = 0; k < list.size(); ++k) {
                World alone(spinning(integrator));
                const BodyId id = addTop(alone, list[k], static_cast<int>(k));
                for (int i = 0; i < 120; ++i) alone.step(Real(1) / 60);
                EXPECT_TRUE(sameBits(alone.orientation(id), together.orientation(ids[k]))) << "body " << k;
                EXPECT_TRUE(sameBits(alone.angularVelocity(id), together.angularVelocity(ids[k]))) << "body " << k;
            }
        }
    }
}

// Torque-free: each grouped body keeps its world angular momentum L = I_w w
// (the drift turns it at constant L; float storage of q and w walks it only
// by roundings) and its kinetic energy w.L / 2 to second order in the step.
TEST(PairedDrift, GeneralInertiaBodiesKeepTheirAngularMomentum) {
    std::vector<Top> list = tumblers();
    list.resize(5);
    World world(worldDef(Integrator::SemiImplicitEuler, 4, {0, 0, 0}));
    std::vector<BodyId> ids;
    std::vector<Vec3> l0;
    std::vector<Real> e0;
    for (std::size_t k = 0; k < list.size(); ++k) {
        ids.push_back(addTop(world, list[k], static_cast<int>(k)));
        const Mat3 inertia = world.localInertia(ids[k]);  // q0 = identity: world and body axes agree
        l0.push_back(inertia * list[k].w0);
        e0.push_back(Real(0.5) * dot(list[k].w0, l0.back()));
    }
    for (int i = 0; i < 600; ++i) world.step(Real(1) / 60);
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Mat3 r = toMat3(world.orientation(ids[k]));
        const Vec3 w = world.angularVelocity(ids[k]);
        const Vec3 l = r * world.localInertia(ids[k]) * transpose(r) * w;
        // Measured: at most 2.0e-6 relative over the 2,400 sub-steps.
        EXPECT_LT(length(l - l0[k]) / length(l0[k]), 2e-5) << "body " << k;
        // The midpoint drift is second order: measured at most 6.4e-6 of the
        // energy at these spins (|w| h up to 0.022 rad per sub-step).
        EXPECT_LT(std::fabs(Real(0.5) * dot(w, l) - e0[k]) / e0[k], 1e-4) << "body " << k;
    }
}

// Axisymmetric bodies without spin (L = 0: dropped at rest, as ConvexVsMesh's
// 1764 bodies fall) drift in the lanes with the general path's branch for
// L = 0 (driftLanes): no precession, the spin by a zero half-angle, and the
// quaternion normalised in double. The exact reference, per sub-step: q has
// no zero component here, so the spin q (1, +-0 e_K) gives q back, and
//     q' = float(q_i / sqrt(qw^2 + qx^2 + qy^2 + qz^2))   (double, this order),
// w stays zero. Seven bodies about y (a group of four, a pair and one alone),
// four about z and one about x, each at its own tilt, falling far apart.
TEST(PairedDrift, BodiesWithoutSpinKeepTheGeneralPathsBits) {
    const int substeps = 2;
    World world(worldDef(Integrator::SemiImplicitEuler, substeps));
    std::vector<BodyId> ids;
    std::vector<Quat> expected;
    const Shape shapes[] = {Shape::capsule(Real(0.1), Real(0.4)), Shape::cylinder(Real(0.3), Real(0.1)),
                            Shape::box({Real(0.3), Real(0.3), Real(0.1)}), Shape::box({Real(0.5), Real(0.2), Real(0.2)})};
    const int shapeOf[12] = {0, 1, 0, 1, 0, 1, 0, 2, 2, 2, 2, 3};  // y x7, z x4, x x1
    for (int k = 0; k < 12; ++k) {
        BodyDef d;
        d.shape = shapes[shapeOf[k]];
        d.mass = 2;
        d.position = {static_cast<Real>(10 * k), 50, 0};
        // Not unit length in float (as any stored orientation): the first
        // normalisation changes its bits, the later ones may.
        const Real t = Real(0.3) + Real(0.17) * static_cast<Real>(k);
        d.orientation = normalize(Quat{std::cos(t), Real(0.6) * std::sin(t), Real(-0.48) * std::sin(t), Real(0.64) * std::sin(t)});
        ids.push_back(world.createBody(d));
        expected.push_back(world.orientation(ids.back()));
    }
    for (int step = 0; step < 30; ++step) {
        world.step(Real(1) / 60);
        for (std::size_t k = 0; k < ids.size(); ++k) {
            for (int s = 0; s < substeps; ++s) {
                Quat& q = expected[k];
                const double w = q.w, x = q.x, y = q.y, z = q.z;
                const double invNorm = 1 / std::sqrt(w * w + x * x + y * y + z * z);
                q = Quat{static_cast<Real>(w * invNorm), static_cast<Real>(x * invNorm), static_cast<Real>(y * invNorm),
                         static_cast<Real>(z * invNorm)};
            }
            ASSERT_TRUE(sameBits(world.orientation(ids[k]), expected[k])) << "body " << k << ", step " << step;
            const Vec3 w = world.angularVelocity(ids[k]);
            ASSERT_TRUE(w.x == 0 && w.y == 0 && w.z == 0) << "body " << k << ", step " << step;
        }
    }
}
