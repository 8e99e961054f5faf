// Cloth on the task system (docs/particles.md, "Threads"): the self-collision
// search in fixed blocks of sorted particles, joined in block order, and the
// large constraint colours in ranges of whole SIMD chunks. Both must give the
// bits one thread gives, for any worker count and scheduler.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "fulcrum/task_system.hpp"
#include "reverse_scheduler.hpp"
#include "world/world_access.hpp"
#include "math/real_bits.hpp"

using namespace fulcrum;

namespace {

// Records the ranges it is handed (then runs them last to first, like
// test::ReverseScheduler), so the test knows the parallel paths ran.
class RecordingScheduler final : public TaskSystem {
public:
    std::uint32_t searchCalls = 0;  // calls of 9 ranges of minRange 1: the self-collision search blocks
    std::uint32_t workerCount() const noexcept override { return 2; }
    void parallelFor(std::uint32_t count, std::uint32_t minRange, RangeFn fn) override {
        if (count == 9 && minRange == 1) ++searchCalls;
        const std::uint32_t size = std::min(std::max(minRange, 1u), std::max(count, 1u));
        const std::uint32_t ranges = count / size;
        for (std::uint32_t r = ranges; r-- > 0;) fn(r * size, r + 1 == ranges ? count : (r + 1) * size, r % 2);
    }
};

// A 48 x 48 cloth (2,304 particles: colours of ~1,130 constraints, 9 search
// blocks) dropped on a static sphere, with a free box lying on the sphere's
// side of the ground for the two-way coupling.
World buildScene() {
    World world;
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);
    BodyDef ball;
    ball.type = BodyType::Static;
    ball.shape = Shape::sphere(Real(0.6));
    ball.position = {0, Real(0.8), 0};
    world.createBody(ball);
    BodyDef box;
    box.shape = Shape::box({Real(0.2), Real(0.2), Real(0.2)});
    box.mass = 1;
    box.position = {Real(0.9), Real(0.2), 0};
    world.createBody(box);
    ClothDef cloth;
    cloth.size = {48, 48};
    cloth.spacing = Real(0.05);
    cloth.origin = {Real(-1.175), Real(1.8), Real(-1.175)};
    cloth.bendCompliance = Real(0.1);
    world.createCloth(cloth);
    return world;
}

std::uint64_t hashParticles(const World& world) {
    std::uint64_t h = 14695981039346656037ull;
    for (const ParticleSystemId id : world.particleSystems()) {
        for (const Vec3& x : world.particlePositions(id)) {
            for (const Real v : {x.x, x.y, x.z}) h = (h ^ std::bit_cast<fulcrum::detail::RealBits>(v)) * 1099511628211ull;
        }
    }
    for (const BodyId b : world.bodies()) {
        const Vec3 p = world.position(b);
        for (const Real v : {p.x, p.y, p.z}) h = (h ^ std::bit_cast<fulcrum::detail::RealBits>(v)) * 1099511628211ull;
    }
    return h;
}

// 60 steps: the cloth lands on the sphere and drapes (self-collision
// searches happen while it folds). Physics check: no particle centre inside
// the sphere by more than the particle radius (2 cm) and none below the
// ground, and the cloth's structural edges stretched by under 2 % on average.
TEST(ParticleThreads, ClothIsBitIdenticalForAnyThreadCountAndScheduler) {
    constexpr int kSteps = 60;
    const Real dt = Real(1) / 60;
    std::vector<std::uint64_t> reference;
    {
        World world = buildScene();
        world.setThreadCount(1);
        for (int s = 0; s < kSteps; ++s) {
            world.step(dt);
            reference.push_back(hashParticles(world));
        }
        const ParticleSystemId id = world.particleSystems()[0];
        for (const Vec3& x : world.particlePositions(id)) {
            EXPECT_GT(length(x - Vec3{0, Real(0.8), 0}), Real(0.6) - Real(0.02));
            EXPECT_GT(x.y, Real(-0.02));
        }
        EXPECT_LT(std::abs(world.particleReport(id).meanStretch), Real(0.02));
    }
    test::ReverseScheduler reverse;
    RecordingScheduler recording;
    struct Config {
        const char* name;
        int threads;
        TaskSystem* user;
    };
    const Config configs[] = {{"pool threads=2", 2, nullptr},
                              {"pool threads=3", 3, nullptr},
                              {"user ReverseScheduler", 1, &reverse},
                              {"user RecordingScheduler", 1, &recording}};
    for (const Config& config : configs) {
        World world = buildScene();
        world.setThreadCount(config.threads);
        world.setTaskSystem(config.user);
        for (int s = 0; s < kSteps; ++s) {
            world.step(dt);
            ASSERT_EQ(hashParticles(world), reference[static_cast<std::size_t>(s)]) << config.name << ", step " << s + 1;
        }
        // 16 sub-steps x 1 iteration per step, all as stages.
        EXPECT_EQ(detail::implOf(world).particles.world.stagedSweeps(), std::uint64_t{16} * kSteps) << config.name;
    }
    EXPECT_GT(recording.searchCalls, 0u) << "the self-collision search did not run on the task system";
}

// The threaded cloth with the rest of the coupling: the cloth of buildScene
// with a corner tied to a free box hanging under it (the World's API ties
// only ropes to bodies, so the ties are added to the internal system), and
// a kinematic paddle sweeping through the cloth (a moving shape: its
// contacts test every particle). Every step must be one thread's bits.
World buildTiedScene() {
    World world = buildScene();
    BodyDef weight;
    weight.shape = Shape::box({Real(0.1), Real(0.1), Real(0.1)});
    weight.mass = Real(2);
    weight.position = {Real(-1.175), Real(1.6), Real(-1.175)};
    const BodyId tied = world.createBody(weight);
    BodyDef paddle;
    paddle.type = BodyType::Kinematic;
    paddle.shape = Shape::box({Real(0.05), Real(0.4), Real(0.8)});
    paddle.position = {Real(-1.3), Real(1.2), Real(0.5)};
    const BodyId moving = world.createBody(paddle);
    world.setLinearVelocity(moving, {Real(2), 0, 0});
    const ParticleSystemId id = world.particleSystems()[0];
    ParticleSystem& cloth = detail::implOf(world).particles.world.system(id);
    for (const std::uint32_t corner : {0u, 1u}) {  // a corner particle and its neighbour
        ParticleAttachment a;
        a.particle = corner;
        a.body = tied.index;
        a.localAnchor = cloth.position[corner] - weight.position;  // the box is unrotated, its centre of mass at its origin
        a.resolved = true;
        cloth.attachments.push_back(a);
    }
    return world;
}

TEST(ParticleThreads, TiesAndMovingShapesAreBitIdenticalForAnyThreadCount) {
    constexpr int kSteps = 45;
    const Real dt = Real(1) / 60;
    std::vector<std::uint64_t> reference;
    Vec3 paddleAt;
    {
        World world = buildTiedScene();
        world.setThreadCount(1);
        for (int s = 0; s < kSteps; ++s) {
            world.step(dt);
            reference.push_back(hashParticles(world));
        }
        // Physics: the corners stay tied to the box (rigid ties, within
        // 5 mm of their anchors), the cloth stretches under 2 % on average,
        // and the paddle (moving +x at 2 m/s) pushed cloth ahead of it: no
        // particle centre is inside its box by more than the particle radius.
        const ParticleSystemId id = world.particleSystems()[0];
        const auto x = world.particlePositions(id);
        const BodyId tied = world.bodies()[3];
        for (const ParticleAttachment& a : detail::implOf(world).particles.world.system(id).attachments) {
            const Vec3 anchor = world.position(tied) + rotate(world.orientation(tied), a.localAnchor);
            EXPECT_LT(length(x[a.particle] - anchor), Real(0.005)) << "corner " << a.particle;
        }
        EXPECT_LT(std::abs(world.particleReport(id).meanStretch), Real(0.02));
        const BodyId paddle = world.bodies()[4];
        paddleAt = world.position(paddle);
        EXPECT_NEAR(paddleAt.x, Real(-1.3) + Real(2) * dt * kSteps, Real(1e-3));
        for (const Vec3& q : x) {
            const Vec3 d = q - paddleAt;
            const bool inside = std::abs(d.x) < Real(0.05) - Real(0.02) && std::abs(d.y) < Real(0.4) - Real(0.02) &&
                                std::abs(d.z) < Real(0.8) - Real(0.02);
            EXPECT_FALSE(inside) << "a particle inside the paddle at " << q.x << " " << q.y << " " << q.z;
        }
    }
    test::ReverseScheduler reverse;
    struct Config {
        const char* name;
        int threads;
        TaskSystem* user;
    };
    const Config configs[] = {{"pool threads=2", 2, nullptr}, {"pool threads=3", 3, nullptr}, {"user ReverseScheduler", 1, &reverse}};
    for (const Config& config : configs) {
        World world = buildTiedScene();
        world.setThreadCount(config.threads);
        world.setTaskSystem(config.user);
        for (int s = 0; s < kSteps; ++s) {
            world.step(dt);
            ASSERT_EQ(hashParticles(world), reference[static_cast<std::size_t>(s)]) << config.name << ", step " << s + 1;
        }
        EXPECT_EQ(detail::implOf(world).particles.world.stagedSweeps(), std::uint64_t{16} * kSteps) << config.name;
    }
}

}  // namespace
