// Bodies of general inertia (no two principal moments equal, or off-diagonal
// body-axis entries: compounds, rock hulls) drift four at a time where the
// SIMD lanes exist, the rest one by one (driftGeneralQuad and
// driftGeneralInertia, src/dynamics/integrators.cpp). Each lane must do
// exactly the scalar operations: a body's bits may not depend on whether, or
// with which bodies, it was grouped; and a grouped body must still turn at
// constant world angular momentum.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

#include "dynamics/test_scenes.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// A capsule-and-bar compound (Jolt's HighSpeed body) in a few proportions:
// its inertia about the centre of mass has an off-diagonal entry.
Shape capsuleAndBar(Real capsuleRadius, Real bar) {
    const CompoundChild children[2] = {
        {Shape::capsule(capsuleRadius, Real(0.5)), Transform{{0, Real(0.5), 0}, Quat::identity()}},
        {Shape::box({bar, Real(0.125), Real(0.125)}), Transform{{bar, 0, 0}, Quat::identity()}},
    };
    return Shape::compound(children);
}

struct Tumbler {
    Shape shape;
    Vec3 w0;
};

// Eleven bodies: two groups of four and three alone, one at rest (L = 0),
// one spinning beyond the series' range (its group goes through the scalar path).
std::vector<Tumbler> tumblers() {
    return {
        {capsuleAndBar(Real(0.125), Real(0.5)), {Real(1.5), 5, Real(-0.7)}},
        {capsuleAndBar(Real(0.2), Real(0.3)), {Real(-2), Real(0.5), 3}},
        {capsuleAndBar(Real(0.1), Real(0.7)), {Real(0.3), -4, Real(1.1)}},
        {capsuleAndBar(Real(0.125), Real(0.5)), {40, Real(-10), Real(2)}},
        {capsuleAndBar(Real(0.15), Real(0.4)), {Real(2.5), Real(1.5), Real(-1)}},
        {capsuleAndBar(Real(0.125), Real(0.5)), {}},
        {capsuleAndBar(Real(0.125), Real(0.5)), {Real(0.5), 400, Real(0.3)}},
        {capsuleAndBar(Real(0.3), Real(0.2)), {Real(0.7), Real(-0.2), 5}},
        {capsuleAndBar(Real(0.125), Real(0.6)), {Real(-1), 3, Real(2.2)}},
        {capsuleAndBar(Real(0.125), Real(0.5)), {120, 80, Real(-60)}},
        {capsuleAndBar(Real(0.2), Real(0.5)), {Real(0.1), Real(0.2), Real(0.3)}},
    };
}

BodyId addTumbler(World& world, const Tumbler& t, int slot) {
    BodyDef d;
    d.shape = t.shape;
    d.mass = 3;
    d.position = {static_cast<Real>(10 * slot), 0, 0};
    d.angularVelocity = t.w0;
    return world.createBody(d);
}

WorldDef spinning(Integrator integrator) {
    WorldDef def = worldDef(integrator, 2, {0, 0, 0});
    def.maxRotationPerSubstep = std::numeric_limits<Real>::infinity();  // let the fast one go beyond the series' range
    return def;
}

bool sameBits(const Quat& a, const Quat& b) { return std::memcmp(&a, &b, sizeof(Quat)) == 0; }
bool sameBits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

}  // namespace

TEST(GeneralDriftLanes, EveryBodyHasTheBitsItHasAlone) {
    const std::vector<Tumbler> list = tumblers();
    for (const Integrator integrator : {Integrator::SemiImplicitEuler, Integrator::Verlet}) {
        World together(spinning(integrator));
        std::vector<BodyId> ids;
        for (std::size_t k = 0; k < list.size(); ++k) ids.push_back(addTumbler(together, list[k], static_cast<int>(k)));
        // The inertia is general (the lanes' path, not the axisymmetric one).
        const Mat3 inertia = together.localInertia(ids[0]);
        ASSERT_NE(inertia(0, 1), 0);
        for (int i = 0; i < 120; ++i) together.step(Real(1) / 60);
        for (std::size_t k = 0; k < list.size(); ++k) {
            World alone(spinning(integrator));
            const BodyId id = addTumbler(alone, list[k], static_cast<int>(k));
            for (int i = 0; i < 120; ++i) alone.step(Real(1) / 60);
            EXPECT_TRUE(sameBits(alone.orientation(id), together.orientation(ids[k]))) << "body " << k;
            EXPECT_TRUE(sameBits(alone.angularVelocity(id), together.angularVelocity(ids[k]))) << "body " << k;
            EXPECT_TRUE(sameBits(alone.position(id), together.position(ids[k]))) << "body " << k;
        }
    }
}

// The grouped bodies keep their world angular momentum L = R I R^T w (the
// drift's invariant; it is kept to rounding, second order in the turn).
TEST(GeneralDriftLanes, GroupedBodiesKeepTheirAngularMomentum) {
    std::vector<Tumbler> list = tumblers();
    list.resize(4);  // one group of four, under the default spin limit
    World world(worldDef(Integrator::SemiImplicitEuler, 4, {0, 0, 0}));
    std::vector<BodyId> ids;
    std::vector<Vec3> l0;
    for (std::size_t k = 0; k < list.size(); ++k) {
        ids.push_back(addTumbler(world, list[k], static_cast<int>(k)));
        l0.push_back(world.localInertia(ids[k]) * list[k].w0);  // q0 = identity
    }
    for (int i = 0; i < 600; ++i) world.step(Real(1) / 60);
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Mat3 r = toMat3(world.orientation(ids[k]));
        const Vec3 l = r * world.localInertia(ids[k]) * transpose(r) * world.angularVelocity(ids[k]);
        // Measured: at most 1.8e-6 of |L| after 2,400 sub-steps (float rounding).
        EXPECT_LT(length(l - l0[k]) / length(l0[k]), 1e-4) << "body " << k;
    }
}
