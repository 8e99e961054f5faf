// The wide (SIMD) contact solver against the scalar reference
// (src/solver/contact_wide.hpp): the same operations in the same order, so the
// two give the same bodies, step after step, on a pile that exercises every
// branch (speculative and overlapping points, friction inside and on the cone,
// twist, rolling resistance, restitution, kinematic and static partners,
// unequal masses, partly filled blocks). Both must also give the right physics.
#include <gtest/gtest.h>

#include <string>

#include <cmath>
#include <cstdlib>

#include "contacts/helpers.hpp"
#include "fulcrum/task_system.hpp"
#include "support/same_motion.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// A mixed pile: boxes of several sizes and masses, bouncy and rolling spheres,
// a kinematic paddle sweeping through, all dropped onto the ground.
std::vector<BodyId> buildMixedPile(World& world) {
    std::vector<BodyId> ids;
    addGround(world, Real(0.6), Real(0.2));
    for (int k = 0; k < 6; ++k) {
        for (int i = 0; i < 5; ++i) {
            for (int j = 0; j < 5; ++j) {
                const Vec3 p{Real(1.1) * static_cast<Real>(i - 2) + Real(0.13) * static_cast<Real>(k % 3),
                             Real(0.6) + Real(1.2) * static_cast<Real>(k),
                             Real(1.1) * static_cast<Real>(j - 2) - Real(0.07) * static_cast<Real>(k % 2)};
                const int kind = (i + 2 * j + k) % 4;
                BodyDef d;
                d.position = p;
                d.orientation = Quat::fromAxisAngle(normalize(Vec3{1, 2, 3}), Real(0.1) * static_cast<Real>(i + j));
                if (kind == 0) {
                    d.shape = Shape::sphere(Real(0.45));
                    d.mass = 2;
                    d.restitution = Real(0.6);  // bounces above the 1 m/s threshold
                } else if (kind == 1) {
                    d.shape = Shape::sphere(Real(0.4));
                    d.mass = 1;
                    d.rollingResistance = Real(0.1);
                } else if (kind == 2) {
                    d.shape = Shape::box({Real(0.5), Real(0.3), Real(0.4)});
                    d.mass = 5;  // 1:5 mass ratio with its neighbours
                    d.friction = Real(0.3);
                } else {
                    d.shape = Shape::box(Vec3::splat(Real(0.45)));
                    d.mass = 1;
                }
                ids.push_back(world.createBody(d));
            }
        }
    }
    // Six boxes created inside each other: deep overlaps, whose push-out
    // speed each lane shares with its bodies' other deep overlaps (pushLimit).
    for (int i = 0; i < 6; ++i) {
        const Real offset = Real(0.05) * static_cast<Real>(i);
        ids.push_back(addBox(world, {Real(4.5) + offset, Real(0.5) + offset, Real(4.5) - offset}, Vec3::splat(Real(0.45))));
    }
    BodyDef paddle;
    paddle.type = BodyType::Kinematic;
    paddle.shape = Shape::box({Real(0.2), Real(0.5), Real(3)});
    paddle.position = {-4, Real(0.6), 0};
    paddle.linearVelocity = {Real(0.8), 0, 0};
    ids.push_back(world.createBody(paddle));
    return ids;
}

WorldDef awakeWorld() {
    WorldDef d;
    d.sleeping = false;
    return d;
}

// Wide (4 or 8 lanes) and scalar solves give equal positions, orientations
// and velocities after every one of 240 steps (4 s: the fall, the impacts,
// the paddle's sweep and the settling). Equality is exact (==; a zero's sign
// may differ, which no later operation can turn into a different value).
void expectWideAgreesWithScalar(detail::SimdPath path) {
    World wide(awakeWorld()), scalar(awakeWorld());
    ASSERT_EQ(detail::implOf(wide).contactSolver.setSimdPath(path), path);
    detail::implOf(scalar).contactSolver.setSimdPath(detail::SimdPath::Scalar);
    const std::vector<BodyId> a = buildMixedPile(wide);
    const std::vector<BodyId> b = buildMixedPile(scalar);
    std::size_t maxConstraints = 0;
    for (int step = 0; step < 240; ++step) {
        wide.step(kDt);
        scalar.step(kDt);
        maxConstraints = std::max(maxConstraints, detail::implOf(wide).contactSolver.constraintCount());
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_TRUE(test::sameMotion(wide, a[i], scalar, b[i]))
                << detail::simdPathName(path) << ": body " << i << " differs at step " << step;
        }
    }
    // The pile really exercised the solver: well over one block per colour.
    EXPECT_GT(maxConstraints, std::size_t{150});
}

}  // namespace

TEST(WideSolver, FourLanesAgreeWithScalarSolverStepByStep) { expectWideAgreesWithScalar(detail::SimdPath::Sse2); }

TEST(WideSolver, EightLanesAgreeWithScalarSolverStepByStep) {
    if (!detail::avx2Available()) GTEST_SKIP() << "this CPU (or this build) has no AVX2: the 8-lane path cannot run";
    expectWideAgreesWithScalar(detail::SimdPath::Avx2);
}

// FULCRUM_SIMD's values, and a clear error for a value it doesn't know.
TEST(WideSolver, SimdSettingIsParsedOrRejectedWithItsName) {
    EXPECT_EQ(detail::simdPathFromSetting(nullptr), detail::bestSimdPath());
    EXPECT_EQ(detail::simdPathFromSetting(""), detail::bestSimdPath());
    EXPECT_EQ(detail::simdPathFromSetting("scalar"), detail::SimdPath::Scalar);
    EXPECT_EQ(detail::simdPathFromSetting("sse2"), detail::SimdPath::Sse2);
    EXPECT_EQ(detail::simdPathFromSetting("avx2"), detail::bestSimdPath());  // sse2 without AVX2
    try {
        detail::simdPathFromSetting("avx512");
        FAIL() << "an unknown FULCRUM_SIMD value was accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("FULCRUM_SIMD"), std::string::npos) << what;
        EXPECT_NE(what.find("'avx512'"), std::string::npos) << what;
        EXPECT_NE(what.find("scalar, sse2 or avx2"), std::string::npos) << what;
    }
}

// A solver made without FULCRUM_SIMD in the environment takes the widest path
// the CPU runs; asking for AVX2 where it is missing gives SSE2, never a crash.
TEST(WideSolver, DefaultPathIsTheWidestTheCpuRuns) {
    World world(awakeWorld());
    detail::ContactSolver& solver = detail::implOf(world).contactSolver;
    if (std::getenv("FULCRUM_SIMD") == nullptr) {
        EXPECT_EQ(solver.simdPath(), detail::bestSimdPath());
    }
    const detail::SimdPath expected = detail::avx2Available() ? detail::SimdPath::Avx2 : detail::SimdPath::Sse2;
    EXPECT_EQ(solver.setSimdPath(detail::SimdPath::Avx2), expected);
    EXPECT_TRUE(solver.wide());
    solver.setWide(false);
    EXPECT_EQ(solver.simdPath(), detail::SimdPath::Scalar);
}

// Same input, same output: two wide runs of the pile are identical.
TEST(WideSolver, IsDeterministic) {
    World first(awakeWorld()), second(awakeWorld());
    const std::vector<BodyId> a = buildMixedPile(first);
    const std::vector<BodyId> b = buildMixedPile(second);
    run(first, 120);
    run(second, 120);
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(first.position(a[i]), second.position(b[i])) << "body " << i;
        EXPECT_EQ(first.linearVelocity(a[i]), second.linearVelocity(b[i])) << "body " << i;
    }
}

// Both paths give the physics: a pyramid of 10 rows stands 5 s with either
// (no box drifts 5 cm, the top sinks less than 25 cm: the benchmark's
// criteria), and a resting box carries its weight (the contact impulses per
// step sum to m g dt, so it neither sinks nor rises: speed < 1e-3 m/s).
TEST(WideSolver, BothPathsStackAndRest) {
    for (const bool useWide : {true, false}) {
        World world(awakeWorld());
        detail::implOf(world).contactSolver.setWide(useWide);
        addGround(world);
        std::vector<BodyId> boxes;
        std::vector<Vec3> start;
        for (int row = 0; row < 10; ++row) {
            for (int i = 0; i < 10 - row; ++i) {
                const Real x = static_cast<Real>(i) - Real(0.5) * static_cast<Real>(9 - row);
                boxes.push_back(addBox(world, {x, Real(0.5) + static_cast<Real>(row), 0}));
                start.push_back(world.position(boxes.back()));
            }
        }
        const BodyId top = boxes.back();
        const Vec3 topStart = start.back();
        run(world, 300);
        Real drift = 0, speed = 0;
        for (std::size_t i = 0; i < boxes.size(); ++i) {
            const Vec3 d = world.position(boxes[i]) - start[i];
            drift = std::max(drift, std::sqrt(d.x * d.x + d.z * d.z));
            speed = std::max(speed, length(world.linearVelocity(boxes[i])));
        }
        EXPECT_LT(drift, Real(0.05)) << (useWide ? "wide" : "scalar");
        EXPECT_LT(topStart.y - world.position(top).y, Real(0.25)) << (useWide ? "wide" : "scalar");
        EXPECT_LT(speed, Real(1e-3)) << (useWide ? "wide" : "scalar");
    }
}

// The blocks of a colour spread over threads give the same bodies bit for bit
// whatever the thread count (they share no dynamic body): 1, 2 and 3 workers,
// 90 steps of a 240-body pile whose first colours hold more than two tasks' worth of blocks.
TEST(WideSolver, ParallelColoursGiveIdenticalResultsForAnyThreadCount) {
    std::vector<std::vector<Vec3>> positions;
    std::vector<std::vector<Vec3>> velocities;
    for (const std::uint32_t threads : {1u, 2u, 3u}) {
        ThreadPoolDef poolDef;
        poolDef.threads = threads;
        const std::unique_ptr<TaskSystem> pool = makeThreadPool(poolDef);
        World world(awakeWorld());
        // A wide path whatever FULCRUM_SIMD says (the double build's best path is scalar: 4 portable lanes there).
        const detail::SimdPath best = detail::bestSimdPath();
        detail::implOf(world).contactSolver.setSimdPath(best == detail::SimdPath::Scalar ? detail::SimdPath::Sse2 : best);
        detail::implOf(world).contactSolver.setTaskSystem(pool.get());
        addGround(world);
        std::vector<BodyId> ids;
        for (int k = 0; k < 2; ++k) {
            for (int i = 0; i < 12; ++i) {
                for (int j = 0; j < 10; ++j) {
                    const Vec3 p{static_cast<Real>(i - 6) * Real(1.02) + Real(0.1) * static_cast<Real>(k % 2),
                                 Real(0.5) + static_cast<Real>(k), static_cast<Real>(j - 6) * Real(1.02)};
                    ids.push_back((i + j + k) % 3 == 0 ? addSphere(world, p, Real(0.5)) : addBox(world, p));
                }
            }
        }
        run(world, 90);
        // Many blocks per colour, or the test would not run anything in parallel.
        // (A colour is split from 16 blocks on: 18 blocks here with 8 lanes, 36 with 4.)
        EXPECT_GE(detail::implOf(world).contactSolver.largestColourBlocks(), std::size_t{16});
        positions.emplace_back();
        velocities.emplace_back();
        for (BodyId id : ids) {
            positions.back().push_back(world.position(id));
            velocities.back().push_back(world.linearVelocity(id));
        }
        detail::implOf(world).contactSolver.setTaskSystem(nullptr);
    }
    for (std::size_t t = 1; t < positions.size(); ++t) {
        for (std::size_t i = 0; i < positions[0].size(); ++i) {
            ASSERT_EQ(positions[t][i], positions[0][i]) << "body " << i << " with " << t + 1 << " threads";
            ASSERT_EQ(velocities[t][i], velocities[0][i]) << "body " << i << " with " << t + 1 << " threads";
        }
    }
}
