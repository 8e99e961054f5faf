// The multithreaded step gives bit-identical results for every thread count
// and scheduler (docs/threading.md, "What runs in parallel").
//
// Each scene is stepped with the inline task system (threads = 1), the
// built-in pool at 2, 3 and 4 threads, and two user schedulers plugged in with
// World::setTaskSystem: ReverseScheduler (ranges of minRange in reverse order)
// and ScatterScheduler (ranges of 3 indices, far below minRange, in a
// scrambled order under 4 worker indices). Positions, orientations,
// velocities, awake flags, contact reports and contact events must agree to
// the bit after every step: any result that depended on the order in which
// ranges ran, on how they were cut, or on which worker ran them would differ.
//
// The scenes are big enough that the pool really splits the loops: ~600
// bodies (the per-body loops run in ranges of 256) and thousands of contacts
// (ranges of 32). Physics check, so a broken step cannot pass by being broken
// the same way everywhere: nothing sinks through the ground (tolerance 5 cm,
// ten times the solver's resting overlap) and the piles lose energy while
// settling (no object ends above its starting height plus 1 cm).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "../determinism/state_hash.hpp"
#include "fulcrum/scene.hpp"
#include "fulcrum/task_system.hpp"
#include "fulcrum/world.hpp"
#include "ground.hpp"
#include "reverse_scheduler.hpp"

using namespace fulcrum;

namespace {

// Ranges of 3 indices whatever minRange says (the contract's "should"), run
// in the order r * 7 mod n (7 is coprime to n unless n is a multiple of 7;
// then plain reverse), as worker r % 4.
class ScatterScheduler final : public TaskSystem {
public:
    std::uint32_t workerCount() const noexcept override { return 4; }
    void parallelFor(std::uint32_t count, std::uint32_t, RangeFn fn) override {
        if (count == 0) return;
        const std::uint32_t size = 3;
        const std::uint32_t ranges = (count + size - 1) / size;
        for (std::uint32_t k = 0; k < ranges; ++k) {
            const std::uint32_t r = ranges % 7 != 0 ? (k * 7) % ranges : ranges - 1 - k;
            const std::uint32_t begin = r * size;
            const std::uint32_t end = begin + size < count ? begin + size : count;
            fn(begin, end, r % 4);
        }
    }
};

struct Config {
    std::string name;
    int threads = 1;
    TaskSystem* user = nullptr;
};

// Everything a step produces that a user can see, compared bit for bit.
struct Frame {
    std::uint64_t stateHash = 0;
    std::vector<std::uint64_t> contactBits;  // reports and events, flattened
};

void addBits(std::vector<std::uint64_t>& out, const Vec3& v) {
    for (const Real c : {v.x, v.y, v.z}) {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &c, sizeof bits);
        out.push_back(bits);
    }
}

Frame capture(const World& world) {
    Frame f;
    f.stateHash = test::stateHash(world);
    for (const ContactReport& c : world.contacts()) {
        f.contactBits.push_back((std::uint64_t(c.bodyA.index) << 32) | c.bodyB.index);
        addBits(f.contactBits, c.normal);
        addBits(f.contactBits, {c.depth, 0, 0});
        for (const Vec3& p : c.points) addBits(f.contactBits, p);
    }
    for (const auto events : {world.contactBeginEvents(), world.contactEndEvents(), world.sensorBeginEvents(),
                              world.sensorEndEvents()}) {
        f.contactBits.push_back(0xE0E0E0E0u);
        for (const ContactEvent& e : events) f.contactBits.push_back((std::uint64_t(e.bodyA.index) << 32) | e.bodyB.index);
    }
    return f;
}

// Steps a freshly built world `steps` times under each config and expects
// every frame to equal the threads = 1 frames; runs physicsCheck on each
// config's final world.
void expectIdenticalRuns(const std::function<World()>& build, int steps, Real dt,
                         const std::function<void(const World&)>& physicsCheck) {
    test::ReverseScheduler reverse;
    ScatterScheduler scatter;
    const std::vector<Config> configs = {{"threads=1", 1, nullptr},          {"pool threads=2", 2, nullptr},
                                         {"pool threads=3", 3, nullptr},     {"pool threads=4", 4, nullptr},
                                         {"user ReverseScheduler", 1, &reverse}, {"user ScatterScheduler", 1, &scatter}};
    std::vector<Frame> reference;
    for (const Config& config : configs) {
        World world = build();
        world.setThreadCount(config.threads);
        world.setTaskSystem(config.user);
        for (int s = 0; s < steps; ++s) {
            world.step(dt);
            const Frame f = capture(world);
            if (reference.size() < static_cast<std::size_t>(steps)) {
                reference.push_back(f);
                continue;
            }
            const Frame& ref = reference[static_cast<std::size_t>(s)];
            ASSERT_EQ(f.stateHash, ref.stateHash) << config.name << ": bodies/particles differ at step " << s + 1;
            ASSERT_EQ(f.contactBits, ref.contactBits) << config.name << ": contacts differ at step " << s + 1;
        }
        physicsCheck(world);
    }
    EXPECT_GT(reverse.calls, 0u);
}

// A heap of `nx * ny * nz` bodies on a static ground box, stacked in columns
// a hair apart and turned a little each, so contacts exist from the first
// step and the pile collapses sideways (many contacts begin and end).
// parallelMinBodies 0: the built-in pool runs every step, however few bodies
// are awake (the default steps small worlds inline: WorldDef::parallelMinBodies).
World buildPile(bool spheres, int nx, int ny, int nz, std::uint32_t parallelMinBodies = 0) {
    WorldDef def;
    def.parallelMinBodies = parallelMinBodies;
    World world(def);
    test::addGroundSlab(world);
    const Shape shape = spheres ? Shape::sphere(Real(0.5)) : Shape::box({Real(0.5), Real(0.5), Real(0.5)});
    for (int y = 0; y < ny; ++y) {
        for (int z = 0; z < nz; ++z) {
            for (int x = 0; x < nx; ++x) {
                BodyDef d;
                d.shape = shape;
                d.mass = 1;
                const int k = x + 3 * z + 7 * y;
                d.position = {Real(1.1) * static_cast<Real>(x) + Real(0.05) * static_cast<Real>(y % 3),
                              Real(0.5) + Real(1.02) * static_cast<Real>(y),
                              Real(1.1) * static_cast<Real>(z) - Real(0.04) * static_cast<Real>(y % 2)};
                const Real angle = Real(0.15) * static_cast<Real>(k % 5 - 2);
                d.orientation = normalize(Quat{std::cos(angle / 2), Real(0.3) * std::sin(angle / 2),
                                               std::sin(angle / 2), 0});
                world.createBody(d);
            }
        }
    }
    return world;
}

void checkPile(const World& world, int ny) {
    const Real top = Real(0.5) + Real(1.02) * static_cast<Real>(ny - 1);
    for (const BodyId id : world.bodies()) {
        if (world.bodyType(id) == BodyType::Static) continue;
        const Vec3 p = world.position(id);
        ASSERT_GT(p.y, Real(0.5) - Real(0.5) - Real(0.05)) << "a body sank through the ground";
        ASSERT_LT(p.y, top + Real(0.01)) << "a body gained height while the pile settles";
    }
}

}  // namespace

TEST(ThreadedStep, BoxPileIsBitIdenticalForAnyThreadCount) {
    constexpr int kY = 6;
    expectIdenticalRuns([] { return buildPile(false, 10, kY, 10); }, 30, Real(1) / 60,
                        [](const World& w) { checkPile(w, kY); });
}

TEST(ThreadedStep, SpherePileIsBitIdenticalForAnyThreadCount) {
    constexpr int kY = 6;
    expectIdenticalRuns([] { return buildPile(true, 10, kY, 10); }, 30, Real(1) / 60,
                        [](const World& w) { checkPile(w, kY); });
}

// The stages the piles above do not take, under every integrator:
// ForceCallbacks (called in body order on one thread) and springs as
// single-unit stages between the per-body ones, Verlet's predictor and second
// kick as per-body stages around a force evaluation, explicit Euler's drift
// with the old velocity. A pile of boxes, every 7th with a callback that reads
// its velocity and the time, every 5th tied to the one before by a spring at
// rest. Physics check as for the piles.
TEST(ThreadedStep, CallbacksSpringsAndEveryIntegratorAreBitIdenticalForAnyThreadCount) {
    constexpr int kY = 4;
    for (const Integrator integrator : {Integrator::Verlet, Integrator::ExplicitEuler, Integrator::SemiImplicitEuler}) {
        SCOPED_TRACE(static_cast<int>(integrator));
        const auto build = [&] {
            World world = buildPile(false, 8, kY, 8);
            world.setIntegrator(integrator);
            int k = 0;
            BodyId previous;
            for (const BodyId id : world.bodies()) {
                if (world.bodyType(id) == BodyType::Static) continue;
                if (k % 7 == 0) {
                    world.setForceCallback(id, [](const BodyKinematics& b) {
                        return Wrench{b.linearVelocity * (-Real(0.5) * b.mass) + Vec3{Real(0.2) * std::sin(b.time), 0, 0},
                                      Vec3{}};
                    });
                }
                if (k % 5 == 0 && !previous.isNull()) {
                    SpringDef spring;
                    spring.bodyA = previous;
                    spring.bodyB = id;
                    spring.anchorA = world.position(previous);
                    spring.anchorB = world.position(id);
                    spring.restLength = length(spring.anchorB - spring.anchorA);
                    spring.stiffness = 20;
                    spring.damping = Real(0.5);
                    world.createSpring(spring);
                }
                previous = id;
                ++k;
            }
            return world;
        };
        expectIdenticalRuns(build, 30, Real(1) / 60, [](const World& w) { checkPile(w, kY); });
    }
}

// Islands and sleep timers (SleepManager::update runs its per-constraint and
// per-body loops on the task system): a layer of 600 boxes resting on the
// ground in 20 rows of touching boxes, every row one island through its
// contacts. At the end of each even row a kinematic sphere spins about the
// row's axis (its contact point lies on the spin axis, so it pushes nothing)
// and keeps its row's island awake; the odd rows fall asleep. Every body must
// fall asleep (or not) at the same step for every thread count and scheduler
// (the state hash includes the awake flags): a dropped range of the timers
// would leave an island awake, a dropped range of the "joins" (touching
// contacts between awake bodies) would split an even row and let part of it
// sleep. Physics check: even rows awake, odd rows asleep, every box within
// 1 cm of where it rests.
TEST(ThreadedStep, RestingLayerFallsAsleepTheSameForAnyThreadCount) {
    constexpr int kRows = 20, kPerRow = 30;
    const auto rowZ = [](int r) { return Real(-15) + Real(1.5) * static_cast<Real>(r); };
    const auto build = [&] {
        WorldDef def;
        def.parallelMinBodies = 0;  // the odd rows' sleep takes the awake count below the default
        World world(def);
        test::addGroundSlab(world);
        for (int r = 0; r < kRows; ++r) {
            for (int i = 0; i < kPerRow; ++i) {
                BodyDef d;
                d.shape = Shape::box({Real(0.5), Real(0.5), Real(0.5)});
                d.mass = 1;
                d.position = {Real(-15) + static_cast<Real>(i), Real(0.5), rowZ(r)};
                world.createBody(d);
            }
            if (r % 2 != 0) continue;
            BodyDef spinner;
            spinner.type = BodyType::Kinematic;
            spinner.shape = Shape::sphere(Real(0.5));
            spinner.position = {Real(-15) + static_cast<Real>(kPerRow), Real(0.5), rowZ(r)};
            spinner.angularVelocity = {3, 0, 0};
            world.createBody(spinner);
        }
        return world;
    };
    expectIdenticalRuns(build, 60, Real(1) / 60, [&](const World& w) {
        for (const BodyId id : w.bodies()) {
            if (w.bodyType(id) != BodyType::Dynamic) continue;
            const Vec3 p = w.position(id);
            const int row = static_cast<int>(std::lround((p.z + Real(15)) / Real(1.5)));
            ASSERT_EQ(w.isAwake(id), row % 2 == 0) << "row " << row << ": only the rows with a spinner stay awake";
            ASSERT_NEAR(p.y, Real(0.5), Real(0.01)) << "a resting box moved";
            ASSERT_NEAR(p.z, rowZ(row), Real(0.01)) << "a resting box moved";
        }
    });
}

// Joints (a ball-joint chain), a rope tied to a box, a cloth on a sphere and a
// small box pile (tests/determinism's mixed scene), long enough for the pile
// to settle and fall asleep. Physics check: the rope's pinned end holds and
// every particle stays above the ground (2 cm: particle radius 3 cm).
TEST(ThreadedStep, JointsAndParticlesAreBitIdenticalForAnyThreadCount) {
    const Scene scene = parseScene(test::kMixedScene, "mixed");
    expectIdenticalRuns([&] { return buildWorld(scene); }, 120, scene.dt, [](const World& w) {
        for (const ParticleSystemId id : w.particleSystems()) {
            for (const Vec3& x : w.particlePositions(id)) ASSERT_GT(x.y, Real(-0.02)) << "a particle fell through";
        }
    });
}

// Changing the thread count or the scheduler between steps (the pool is
// re-created, per-worker buffers re-sized) changes nothing either: a pile
// stepped with threads 1, 2, 4, 3, a user scheduler, then the built-in pool
// again, ends bit-identical to one stepped on a single thread throughout.
// Physics check as for the piles.
TEST(ThreadedStep, SwitchingThreadsBetweenStepsKeepsTheResult) {
    constexpr int kY = 4;
    test::ReverseScheduler reverse;
    World single = buildPile(false, 10, kY, 10);
    World switching = buildPile(false, 10, kY, 10);
    const int threadsPerStep[] = {1, 2, 4, 3, 0, 2, 1, 3};  // 0: the user scheduler
    for (int s = 0; s < 24; ++s) {
        const int t = threadsPerStep[s % 8];
        switching.setTaskSystem(t == 0 ? &reverse : nullptr);
        if (t > 0) switching.setThreadCount(t);
        single.step(Real(1) / 60);
        switching.step(Real(1) / 60);
        ASSERT_EQ(test::stateHash(switching), test::stateHash(single)) << "step " << s + 1 << " with threads " << t;
    }
    checkPile(switching, kY);
}

// Small steps run on the calling thread (WorldDef::parallelMinBodies, default
// 512 awake bodies). The choice is made per step, so a pile whose awake count
// crosses the threshold switches between the pool and the caller mid-run; the
// bits must not notice. A 400-box pile stepped on the pool at 2 threads with
// the threshold at 0 (always the pool), at the default (always inline here)
// and at 200 (the pool while all 400 are awake, inline once the pile falls
// asleep at step ~140) ends bit-identical to one thread after every step. Physics check as for the piles.
TEST(ThreadedStep, SmallStepsOnTheCallerKeepTheResult) {
    constexpr int kY = 4;
    World single = buildPile(false, 10, kY, 10);
    std::vector<World> threaded;
    for (const std::uint32_t minBodies : {0u, 512u}) {
        threaded.push_back(buildPile(false, 10, kY, 10, minBodies));
        threaded.back().setThreadCount(2);
    }
    threaded.push_back(buildPile(false, 10, kY, 10));
    threaded.back().setThreadCount(2);
    threaded.back().setParallelMinBodies(200);  // the setter, as WorldDef::parallelMinBodies
    ASSERT_EQ(threaded.back().settings().parallelMinBodies, 200u);
    for (int s = 0; s < 150; ++s) {
        single.step(Real(1) / 60);
        for (World& w : threaded) {
            w.step(Real(1) / 60);
            ASSERT_EQ(test::stateHash(w), test::stateHash(single)) << "step " << s + 1 << ", minimum "
                                                                   << w.settings().parallelMinBodies;
        }
    }
    checkPile(threaded.back(), kY);
}
