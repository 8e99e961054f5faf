// The position stage's rotation work four bodies at a time
// (src/dynamics/pose_lanes.hpp): an isotropic body's rotation
// (integrateRotation) and the pose change since the step's start
// (stepRotationVector), one body per SIMD lane (SSE2, the x86-64 baseline,
// whatever FULCRUM_SIMD picks for the solver). Each lane must give the bits
// of the scalar function, for every lane count (1 to 4: the tail lanes), for
// inputs on each of the scalar function's paths (the first-order map under
// 1e-9 rad, the exact map, half angles the lanes leave to the scalar
// function), and so must whole worlds stepped with the lanes and without
// (detail::setPoseLanesEnabled(false)) at one thread and three.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "determinism/state_hash.hpp"
#include "dynamics/body_store.hpp"
#include "dynamics/pose_lanes.hpp"
#include "fulcrum/world.hpp"

using namespace fulcrum;

namespace {

bool sameBits(const Quat& a, const Quat& b) { return std::memcmp(&a, &b, sizeof(Quat)) == 0; }
bool sameBits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

Quat randomRotation(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    for (;;) {
        const Quat q{static_cast<Real>(u(rng)), static_cast<Real>(u(rng)), static_cast<Real>(u(rng)),
                     static_cast<Real>(u(rng))};
        if (length(q) > Real(0.1)) return normalize(q);
    }
}

// A direction times a magnitude 10^e, e in [-12, 3]: rotations per sub-step
// from far below 1e-9 rad to several radians.
Vec3 randomSpin(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1), e(-12, 3);
    const Vec3 dir = normalize(Vec3{static_cast<Real>(u(rng)), static_cast<Real>(u(rng)), static_cast<Real>(u(rng))});
    return dir * static_cast<Real>(std::pow(10.0, e(rng)));
}

}  // namespace

TEST(PoseLanes, RotationsHaveTheScalarBitsInEveryLane) {
    std::mt19937 rng(20261129);
    const Real h = Real(1) / 300;
    int firstOrder = 0, exactMap = 0, beyond = 0;
    for (int round = 0; round < 3000; ++round) {
        const int n = 1 + round % 4;
        Quat q[4], expected[4];
        Vec3 w[4];
        Quat* qp[4];
        const Vec3* wp[4];
        for (int k = 0; k < n; ++k) {
            q[k] = randomRotation(rng);
            w[k] = round % 50 == 0 && k == 0 ? Vec3{} : randomSpin(rng);  // and at rest
            expected[k] = integrateRotation(q[k], w[k], h);
            qp[k] = &q[k];
            wp[k] = &w[k];
            const Real angle = length(w[k]) * h;
            (angle < Real(1e-9) ? firstOrder : Real(0.5) * angle <= Real(0.75) ? exactMap : beyond) += 1;
        }
        detail::integrateRotations(qp, wp, n, h);
        for (int k = 0; k < n; ++k) {
            ASSERT_TRUE(sameBits(q[k], expected[k])) << "round " << round << ", lane " << k << " of " << n;
        }
    }
    // Every path was exercised.
    EXPECT_GT(firstOrder, 100);
    EXPECT_GT(exactMap, 100);
    EXPECT_GT(beyond, 100);
}

TEST(PoseLanes, RotationVectorsHaveTheScalarBitsInEveryLane) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> turn(-3.2, 3.2), small(-0.3, 0.3);
    int series = 0, exact = 0;
    for (int round = 0; round < 3000; ++round) {
        const int n = 1 + round % 4;
        Quat q[4], start[4];
        Vec3 out[4], expected[4];
        const Quat* qp[4];
        const Quat* sp[4];
        Vec3* op[4];
        for (int k = 0; k < n; ++k) {
            start[k] = randomRotation(rng);
            // Turns since the step's start from none to large, and the
            // quaternion's double cover (-q: the shortest arc's negation).
            const double angle = round % 3 == 0 ? turn(rng) : small(rng) * std::pow(10.0, -(round % 7));
            const Vec3 axis = normalize(randomSpin(rng));
            q[k] = Quat::fromAxisAngle(axis, static_cast<Real>(angle)) * start[k];
            if (round % 5 == 1) q[k] = -q[k];
            if (round % 97 == 0) q[k] = start[k];
            const Quat r = q[k] * conjugate(start[k]);
            expected[k] = detail::stepRotationVector(r);
            const Real s2 = lengthSquared(r.vec());
            (s2 < Real(0.01) * r.w * r.w ? series : exact) += 1;
            qp[k] = &q[k];
            sp[k] = &start[k];
            op[k] = &out[k];
        }
        detail::stepRotationVectors(qp, sp, op, n);
        for (int k = 0; k < n; ++k) {
            ASSERT_TRUE(sameBits(out[k], expected[k])) << "round " << round << ", lane " << k << " of " << n;
        }
    }
    EXPECT_GT(series, 100);
    EXPECT_GT(exact, 100);
}

namespace {

// 1 to 9 bodies (cubes and spheres: isotropic; a brick and a capsule: not)
// dropped and spun on the ground, random masses and spins from tiny to fast;
// the state hash after every step.
std::vector<std::uint64_t> worldHashes(int bodies, int threads, bool lanes, bool spinLimit) {
    detail::setPoseLanesEnabled(lanes);
    WorldDef def;
    def.threads = threads;
    def.parallelMinBodies = 0;
    if (!spinLimit) def.maxRotationPerSubstep = std::numeric_limits<Real>::infinity();
    World world(def);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({40, 1, 40});
    ground.position = {0, -1, 0};
    world.createBody(ground);
    std::mt19937 rng(static_cast<std::uint32_t>(bodies));
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < bodies; ++i) {
        BodyDef d;
        switch (i % 4) {
            case 0: d.shape = Shape::box({Real(0.5), Real(0.5), Real(0.5)}); break;
            case 1: d.shape = Shape::sphere(Real(0.4)); break;
            case 2: d.shape = Shape::box({Real(0.3), Real(0.3), Real(0.3)}); break;
            default: d.shape = i % 8 == 3 ? Shape::box({Real(0.5), Real(0.2), Real(0.3)}) : Shape::capsule(Real(0.2), Real(0.3));
        }
        d.mass = static_cast<Real>(0.5 + 4 * u(rng));
        d.position = {static_cast<Real>(2 * i - bodies), static_cast<Real>(0.5 + 1.5 * u(rng)), 0};
        d.orientation = randomRotation(rng);
        d.angularVelocity = randomSpin(rng) * static_cast<Real>(i % 3 == 2 ? 10 : 1);
        world.createBody(d);
    }
    std::vector<std::uint64_t> hashes;
    for (int s = 0; s < 90; ++s) {
        world.step(Real(1) / 60);
        hashes.push_back(test::stateHash(world));
    }
    detail::setPoseLanesEnabled(false);
    return hashes;
}

}  // namespace

TEST(PoseLanes, WorldsHaveTheBitsOfTheScalarPath) {
    for (int bodies = 1; bodies <= 9; ++bodies) {
        for (const bool spinLimit : {true, false}) {
            const std::vector<std::uint64_t> scalar = worldHashes(bodies, 1, false, spinLimit);
            for (const int threads : {1, 3}) {
                const std::vector<std::uint64_t> lanes = worldHashes(bodies, threads, true, spinLimit);
                ASSERT_EQ(lanes.size(), scalar.size());
                for (std::size_t s = 0; s < lanes.size(); ++s) {
                    ASSERT_EQ(lanes[s], scalar[s]) << bodies << " bodies, threads " << threads << ", spin limit "
                                                   << spinLimit << ", step " << s;
                }
            }
        }
    }
}
