// The position stage's rotation work four bodies at a time
// (src/dynamics/pose_lanes.hpp): an isotropic body's rotation
// (integrateRotation) and the pose change since the step's start
// (stepRotationVector), one body per SIMD lane (SSE2, the x86-64 baseline,
// whatever FULCRUM_SIMD picks for the solver). Each lane must give the bits
// of the scalar function, for every lane count (1 to 4: the tail lanes), for
// inputs on each of the scalar function's paths (the first-order map under
// 1e-9 rad, the exact map, half angles the lanes leave to the scalar
// function), whichever bodies share its group, and so must whole worlds
// stepped with the lanes and without (detail::setPoseLanesEnabled(false)) at
// one thread and three, and with the lanes at one to four threads.
#include <gtest/gtest.h>

#include <algorithm>
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

// A list of bodies on every path of both functions (rotations at rest, under
// 1e-9 rad, in the exact map's range and beyond it; turns since the step's
// start in the series' range and beyond; a non-finite spin), as the position
// stage and the contact deltas meet them.
struct BodyList {
    std::vector<Quat> q, start;
    std::vector<Vec3> w;
};

BodyList bodyList(std::mt19937& rng, int count) {
    std::uniform_real_distribution<double> small(-0.3, 0.3), turn(-3.2, 3.2);
    BodyList list;
    std::uniform_real_distribution<double> u(0.1, 1);
    for (int i = 0; i < count; ++i) {
        // Some turned about a coordinate axis only: their zero components
        // show a first-order step that a general orientation rounds away.
        const Vec3 axis = i % 3 == 1 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
        list.q.push_back(i % 6 < 2 ? Quat::fromAxisAngle(axis, static_cast<Real>(4 * u(rng))) : randomRotation(rng));
        Vec3 spin = randomSpin(rng);
        // Just under the first-order map's limit (1e-9 rad in a step of 1/240 s).
        if (i % 4 == 1) spin = normalize(spin) * static_cast<Real>(240e-9 * u(rng));
        if (i % 11 == 5) spin = Vec3{};
        if (i % 17 == 9) spin.y = std::numeric_limits<Real>::quiet_NaN();
        list.w.push_back(spin);
        const double angle = i % 3 == 0 ? turn(rng) : small(rng) * std::pow(10.0, -(i % 5));
        list.start.push_back(Quat::fromAxisAngle(normalize(randomSpin(rng)), static_cast<Real>(angle)) * list.q.back());
    }
    return list;
}

// Runs both lane functions over `order` (indices into the list) cut into
// groups of the given sizes (each 1 to 4, summing to order.size()), and
// checks every body against the scalar functions bit for bit.
void expectScalarBitsInGroups(const BodyList& list, const std::vector<std::size_t>& order,
                              const std::vector<int>& groupSizes, const char* what) {
    std::vector<Quat> q = list.q;
    std::vector<Vec3> out(list.q.size());
    std::size_t next = 0;
    for (const int n : groupSizes) {
        Quat* qp[4];
        const Vec3* wp[4];
        const Quat* rp[4];
        const Quat* sp[4];
        Vec3* op[4];
        for (int k = 0; k < n; ++k) {
            const std::size_t i = order[next + static_cast<std::size_t>(k)];
            qp[k] = &q[i];
            wp[k] = &list.w[i];
            rp[k] = &list.q[i];
            sp[k] = &list.start[i];
            op[k] = &out[i];
        }
        detail::integrateRotations(qp, wp, n, Real(1) / 240);
        detail::stepRotationVectors(rp, sp, op, n);
        next += static_cast<std::size_t>(n);
    }
    ASSERT_EQ(next, order.size());
    for (const std::size_t i : order) {
        const Quat expected = integrateRotation(list.q[i], list.w[i], Real(1) / 240);
        const Vec3 expectedDelta = detail::stepRotationVector(list.q[i] * conjugate(list.start[i]));
        ASSERT_TRUE(sameBits(q[i], expected)) << what << ": rotation of body " << i;
        ASSERT_TRUE(sameBits(out[i], expectedDelta)) << what << ": rotation vector of body " << i;
    }
}

// Groups of four from the front, the rest in one (as integratePositions and
// updateDeltasInLanes cut a thread's range).
std::vector<int> foursFromTheFront(std::size_t count) {
    std::vector<int> sizes(count / 4, 4);
    if (count % 4 != 0) sizes.push_back(static_cast<int>(count % 4));
    return sizes;
}

}  // namespace

// A body's bits must not depend on which bodies share its lanes: the threads'
// ranges decide the groups, so a grouping-dependent lane would make results
// depend on the thread count. Every split of a list into two ranges (each cut
// into fours from its front, as the position stage does), and random
// orders cut into random group sizes, against the scalar functions.
TEST(PoseLanes, ABodysBitsDoNotDependOnItsGroup) {
    detail::setPoseLanesEnabled(true);
    std::mt19937 rng(2026112912);
    const BodyList list = bodyList(rng, 101);
    const std::size_t count = list.q.size();
    std::vector<std::size_t> identity(count);
    for (std::size_t i = 0; i < count; ++i) identity[i] = i;
    for (std::size_t split = 0; split <= count; ++split) {
        std::vector<int> sizes = foursFromTheFront(split);
        for (const int n : foursFromTheFront(count - split)) sizes.push_back(n);
        expectScalarBitsInGroups(list, identity, sizes, "split");
        if (HasFatalFailure()) return;
    }
    std::uniform_int_distribution<int> groupSize(1, 4);
    for (int round = 0; round < 400; ++round) {
        std::vector<std::size_t> order = identity;
        std::shuffle(order.begin(), order.end(), rng);
        std::vector<int> sizes;
        for (std::size_t left = count; left > 0;) {
            const int n = std::min(groupSize(rng), static_cast<int>(left));
            sizes.push_back(n);
            left -= static_cast<std::size_t>(n);
        }
        expectScalarBitsInGroups(list, order, sizes, "random groups");
        if (HasFatalFailure()) return;
    }
}

namespace {

// 1 to 9 bodies (cubes and spheres: isotropic; a brick and a capsule: not)
// dropped and spun on the ground, random masses and spins from tiny to fast;
// the state hash after every step.
std::vector<std::uint64_t> worldHashes(int bodies, int threads, bool lanes, bool spinLimit) {
    const bool wasEnabled = detail::poseLanesEnabled();
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
    detail::setPoseLanesEnabled(wasEnabled);
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

namespace {

// A pile of 300 bodies, most of them isotropic (cubes and spheres: their
// rotations and contact deltas go through the lanes), with bricks and
// capsules between them, dropped with random spins onto the ground: five
// ranges of 64 bodies for the position stage, so the threads' ranges, and
// with them the lanes' groups, differ with the thread count. The state hash
// after every step.
std::vector<std::uint64_t> pileHashes(int threads) {
    WorldDef def;
    def.threads = threads;
    def.parallelMinBodies = 0;
    World world(def);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({40, 1, 40});
    ground.position = {0, -1, 0};
    world.createBody(ground);
    std::mt19937 rng(300);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 300; ++i) {
        BodyDef d;
        switch (i % 5) {
            case 0:
            case 3: d.shape = Shape::box({Real(0.4), Real(0.4), Real(0.4)}); break;
            case 1:
            case 4: d.shape = Shape::sphere(Real(0.4)); break;
            default: d.shape = i % 2 == 0 ? Shape::box({Real(0.5), Real(0.2), Real(0.3)}) : Shape::capsule(Real(0.2), Real(0.3));
        }
        d.mass = static_cast<Real>(0.5 + 2 * u(rng));
        d.position = {static_cast<Real>(i % 10) - Real(4.5), static_cast<Real>(0.5 + i / 50 + u(rng) * 0.2),
                      static_cast<Real>(i / 10 % 5) - Real(2)};
        d.orientation = randomRotation(rng);
        d.angularVelocity = randomSpin(rng);
        world.createBody(d);
    }
    std::vector<std::uint64_t> hashes;
    for (int s = 0; s < 60; ++s) {
        world.step(Real(1) / 60);
        hashes.push_back(test::stateHash(world));
    }
    return hashes;
}

}  // namespace

// With the lanes on, one world at 1, 2, 3 and 4 threads: the same bits after
// every step (the world test above compares lanes with scalar at one thread
// count each; this one compares thread counts, whose ranges group the lanes).
TEST(PoseLanes, PilesHaveTheSameBitsAtAnyThreadCount) {
    detail::setPoseLanesEnabled(true);
    const std::vector<std::uint64_t> one = pileHashes(1);
    for (const int threads : {2, 3, 4}) {
        const std::vector<std::uint64_t> many = pileHashes(threads);
        ASSERT_EQ(many.size(), one.size());
        for (std::size_t s = 0; s < many.size(); ++s) ASSERT_EQ(many[s], one[s]) << "threads " << threads << ", step " << s;
    }
}
