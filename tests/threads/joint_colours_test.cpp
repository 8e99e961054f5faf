// The joint solver across the task system (docs/threading.md, "Joints"): a
// colour's Gauss-Seidel joints in ranges, and the joint trees side by side,
// give the same bits as everything in order on one thread, for the built-in
// pool at 2, 3 and 4 threads and for a user scheduler that runs the ranges in
// reverse order. The scenes make every parallel path run: colours of more
// than 64 joints (a jointed grid, hinged paddles on a shared static body)
// and dozens of trees (chains) sharing a static and a kinematic end, which the
// solver must never write (a kinematic body keeps its velocity to the bit).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "../determinism/state_hash.hpp"
#include "fulcrum/task_system.hpp"
#include "fulcrum/world.hpp"
#include "reverse_scheduler.hpp"

using namespace fulcrum;

namespace {

// Steps `build()` under each configuration and requires every step's state
// to equal the one-thread run's, bit for bit; `afterStep` (if given) sees
// each step's world, then `check` runs on each configuration's final world
// with the configuration's name.
void expectSameBitsForAnyScheduler(const std::function<World()>& build, int steps,
                                   const std::function<void(const World&, const char* config)>& check,
                                   const std::function<void(const World&, int step)>& afterStep = {}) {
    test::ReverseScheduler reverse;
    struct Config {
        const char* name;
        int threads;
        TaskSystem* user;
    };
    const Config configs[] = {{"threads=1", 1, nullptr},
                              {"pool threads=2", 2, nullptr},
                              {"pool threads=3", 3, nullptr},
                              {"pool threads=4", 4, nullptr},
                              {"user ReverseScheduler", 1, &reverse}};
    std::vector<std::uint64_t> reference;
    for (const Config& config : configs) {
        World world = build();
        world.setThreadCount(config.threads);
        world.setTaskSystem(config.user);
        for (int s = 0; s < steps; ++s) {
            world.step(Real(1) / 60);
            if (afterStep) afterStep(world, s);
            const std::uint64_t hash = test::stateHash(world);
            if (reference.size() < static_cast<std::size_t>(steps)) {
                reference.push_back(hash);
                continue;
            }
            ASSERT_EQ(hash, reference[static_cast<std::size_t>(s)]) << config.name << ": state differs at step " << s + 1;
        }
        check(world, config.name);
    }
    EXPECT_GT(reverse.calls, 0u);
}

WorldDef everyStepInParallel() {
    WorldDef def;
    def.parallelMinBodies = 0;  // the pool runs every loop, however small the world
    return def;
}

// A side x side x side grid of spheres, each joined by ball joints to its
// neighbours below and beside (cycles: Gauss-Seidel rows, ~100 joints per
// colour at side 10), the top layer static; plus a row of 80 paddles hinged
// to the world with motors and limits (one colour of 80 joints whose static
// end they all share).
World buildGridAndPaddles(int side) {
    World world(everyStepInParallel());
    const Real spacing = Real(0.3);
    std::vector<BodyId> ids(static_cast<std::size_t>(side * side * side));
    const auto at = [&](int x, int y, int z) -> BodyId& {
        return ids[static_cast<std::size_t>((y * side + z) * side + x)];
    };
    for (int y = 0; y < side; ++y) {
        for (int z = 0; z < side; ++z) {
            for (int x = 0; x < side; ++x) {
                BodyDef d;
                d.type = y == side - 1 ? BodyType::Static : BodyType::Dynamic;
                d.shape = Shape::sphere(Real(0.1));
                d.mass = 1;
                d.position = {spacing * static_cast<Real>(x), spacing * static_cast<Real>(y), spacing * static_cast<Real>(z)};
                at(x, y, z) = world.createBody(d);
            }
        }
    }
    const auto link = [&](BodyId a, BodyId b) {
        JointDef j;
        j.type = JointType::Ball;
        j.bodyA = a;
        j.bodyB = b;
        j.anchor = (world.position(a) + world.position(b)) * Real(0.5);
        world.createJoint(j);
    };
    for (int y = 0; y < side - 1; ++y) {
        for (int z = 0; z < side; ++z) {
            for (int x = 0; x < side; ++x) {
                link(at(x, y + 1, z), at(x, y, z));
                if (x > 0) link(at(x - 1, y, z), at(x, y, z));
                if (z > 0) link(at(x, y, z - 1), at(x, y, z));
            }
        }
    }
    for (int i = 0; i < 80; ++i) {
        BodyDef d;
        d.shape = Shape::box({Real(0.05), Real(0.3), Real(0.05)});
        d.mass = 2;
        d.position = {Real(0.5) * static_cast<Real>(i), Real(-5), Real(-3)};
        const BodyId paddle = world.createBody(d);
        JointDef j;
        j.type = JointType::Hinge;
        j.bodyB = paddle;
        j.anchor = d.position + Vec3{0, Real(0.3), 0};
        j.axis = {0, 0, 1};
        j.hasLimits = true;
        j.lowerLimit = Real(-0.5);
        j.upperLimit = Real(0.5 + 0.01 * i);
        j.motor.enabled = true;
        j.motor.speed = Real(2);
        j.motor.maxForce = Real(1 + i % 5);
        world.createJoint(j);
    }
    return world;
}

// `chains` chains of `links` capsules joined end to end by ball joints (trees
// the tree solver solves exactly), the first half hanging from the world, the
// other half from one kinematic bar moving at kBarVelocity. Every chain starts
// horizontal (along x), so they swing, each in its own plane 0.5 m from the next.
struct Chains {
    World world{everyStepInParallel()};
    BodyId bar;
    std::vector<JointId> joints;
};

constexpr Vec3 kBarVelocity{Real(0.5), 0, 0};

Chains buildChains(int chains, int links) {
    Chains c;
    BodyDef barDef;
    barDef.type = BodyType::Kinematic;
    barDef.shape = Shape::box({Real(0.05), Real(0.05), Real(20)});  // along z; the chains hang from it 0.5 m apart
    barDef.position = {0, Real(10), 0};
    barDef.linearVelocity = kBarVelocity;
    c.bar = c.world.createBody(barDef);
    const Real linkLength = Real(0.4);
    for (int k = 0; k < chains; ++k) {
        const bool onBar = k >= chains / 2;
        const Vec3 top{0, onBar ? Real(10) : Real(5), Real(0.5) * static_cast<Real>(k)};
        BodyId previous = onBar ? c.bar : kWorldBody;
        for (int i = 0; i < links; ++i) {
            BodyDef d;
            d.shape = Shape::capsule(Real(0.05), linkLength / 2 - Real(0.05));
            d.mass = 1;
            d.position = top + Vec3{linkLength * (static_cast<Real>(i) + Real(0.5)), 0, 0};
            d.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));  // capsule axis along x
            const BodyId link = c.world.createBody(d);
            JointDef j;
            j.type = JointType::Ball;
            j.bodyA = previous;
            j.bodyB = link;
            j.anchor = top + Vec3{linkLength * static_cast<Real>(i), 0, 0};
            c.joints.push_back(c.world.createJoint(j));
            previous = link;
        }
    }
    return c;
}

}  // namespace

// Physics check: the grid hangs from its top layer with every joint within
// 2 cm of closed (the solver holds it to ~5 mm), and every paddle stays inside
// its hinge limits plus 0.05 rad while its motor drives it up against them.
TEST(JointColours, GaussSeidelColoursGiveTheSameBitsOnAnyScheduler) {
    expectSameBitsForAnyScheduler([] { return buildGridAndPaddles(10); }, 20, [](const World& world, const char*) {
        for (const JointId j : world.joints()) {
            ASSERT_LT(world.jointError(j), Real(0.02)) << "a joint opened";
            if (world.jointDef(j).type != JointType::Hinge) continue;
            const Real angle = world.jointPosition(j);
            ASSERT_GT(angle, world.jointDef(j).lowerLimit - Real(0.05)) << "a paddle went past its lower limit";
            ASSERT_LT(angle, world.jointDef(j).upperLimit + Real(0.05)) << "a paddle went past its upper limit";
        }
    });
}

// Physics check: the chains stay joined (worst joint error under 1 cm; the
// projection's slop is 5 mm), and the kinematic bar they hang from is never
// pushed: its velocity keeps its bits and its position is x0 + v t (to float
// rounding of the sums, 1e-4 m over 1.5 s).
TEST(JointColours, TreesSharingStaticAndKinematicEndsGiveTheSameBitsOnAnyScheduler) {
    const int steps = 90;
    expectSameBitsForAnyScheduler([] { return std::move(buildChains(32, 5).world); }, steps, [&](const World& world, const char*) {
        BodyId bar;
        for (const BodyId id : world.bodies()) {
            if (world.bodyType(id) == BodyType::Kinematic) bar = id;
        }
        ASSERT_FALSE(bar.isNull());
        const Vec3 v = world.linearVelocity(bar);
        EXPECT_EQ(v.x, kBarVelocity.x);
        EXPECT_EQ(v.y, kBarVelocity.y);
        EXPECT_EQ(v.z, kBarVelocity.z);
        EXPECT_EQ(world.angularVelocity(bar).x, Real(0));
        EXPECT_EQ(world.angularVelocity(bar).z, Real(0));
        EXPECT_NEAR(world.position(bar).x, kBarVelocity.x * static_cast<Real>(steps) / 60, Real(1e-4));
        for (const JointId j : world.joints()) ASSERT_LT(world.jointError(j), Real(0.01)) << "a chain opened";
    });
}

// Six-DOF joints across the task system: 80 boxes on six-DOF joints to the
// world (a colour of more than 64 joints), each with a different mix of free,
// limited and locked axes, motors and springs, plus 16 chains of point-locked
// six-DOF joints (trees): the same bits on every scheduler; every locked
// linear axis stays within 2 cm.
TEST(JointColours, SixDofJointsGiveTheSameBitsOnAnyScheduler) {
    const auto build = [] {
        World world(everyStepInParallel());
        for (int i = 0; i < 80; ++i) {
            BodyDef d;
            d.shape = Shape::box({Real(0.1), Real(0.2), Real(0.1)});
            d.mass = 1 + Real(i % 3);
            d.position = {Real(0.6) * static_cast<Real>(i), 0, 0};
            d.angularVelocity = {Real(0.3), Real(-0.2), Real(0.5)};
            const BodyId box = world.createBody(d);
            JointDef j;
            j.type = JointType::SixDof;
            j.bodyB = box;
            j.anchor = d.position + Vec3{0, Real(0.2), 0};
            j.axis = {1, 0, 0};
            j.axisY = {0, 1, 0};
            for (int k = 0; k < kSixDofAxes; ++k) {
                SixDofAxis& a = j.axes[static_cast<std::size_t>(k)];
                const int m = (i + k) % 4;
                a.mode = m == 0 ? AxisMode::Free : m == 1 ? AxisMode::Limited : AxisMode::Locked;
                a.lower = Real(-0.3);
                a.upper = Real(0.3);
                if (m == 0) a.spring = {true, 0, Real(20), Real(1)};
                if (m == 1) a.motor = {true, Real(0.5), Real(5)};
            }
            world.createJoint(j);
        }
        for (int c = 0; c < 16; ++c) {
            BodyId previous = kWorldBody;
            for (int i = 0; i < 4; ++i) {
                BodyDef d;
                d.shape = Shape::box({Real(0.2), Real(0.05), Real(0.05)});
                d.mass = 1;
                d.position = {Real(0.4) * static_cast<Real>(i) + Real(0.2), Real(-4), Real(0.5) * static_cast<Real>(c)};
                const BodyId link = world.createBody(d);
                JointDef j;
                j.type = JointType::SixDof;
                j.bodyA = previous;
                j.bodyB = link;
                j.anchor = {Real(0.4) * static_cast<Real>(i), Real(-4), Real(0.5) * static_cast<Real>(c)};
                j.axis = {1, 0, 0};
                j.axes[kAxisRotZ].mode = AxisMode::Free;
                j.axes[kAxisRotX] = {AxisMode::Limited, Real(-0.2), Real(0.2), {}, {}};
                world.createJoint(j);
                previous = link;
            }
        }
        return world;
    };
    expectSameBitsForAnyScheduler(build, 30, [](const World& world, const char*) {
        for (const JointId j : world.joints()) ASSERT_LT(world.jointError(j), Real(0.02)) << "a joint opened";
    });
}

// A sheet like Box3D's joint_grid (spheres 1 m apart, each tied by ball
// joints to the one above and the one beside, the top row static), large
// enough that every per-joint loop of the joint solver runs in ranges: the
// records' build and the structure keys (prepare), the rotation refresh, the
// projection's check (a stage of its own), and the reactions of store().
// The vertical joints of every third column break at 12 spheres' weight, so
// the upper ones break at once and their columns fall, swinging on the
// horizontal joints (the projection's passes then run): the same bits and
// the same break events, in the same order, on every scheduler.
TEST(JointColours, BreakingSheetGivesTheSameBitsAndEventsOnAnyScheduler) {
    const int side = 40;
    const auto build = [&] {
        World world(everyStepInParallel());
        std::vector<BodyId> ids(static_cast<std::size_t>(side * side));
        for (int k = 0; k < side; ++k) {
            for (int i = 0; i < side; ++i) {
                BodyDef d;
                d.type = i == 0 ? BodyType::Static : BodyType::Dynamic;
                d.shape = Shape::sphere(Real(0.4));
                d.mass = 1;
                d.position = {static_cast<Real>(k), -static_cast<Real>(i), 0};
                d.filter.group = -1;  // nothing collides
                ids[static_cast<std::size_t>(k * side + i)] = world.createBody(d);
            }
        }
        const auto link = [&](int a, int b, Vec3 anchor, Real breakForce) {
            JointDef j;
            j.type = JointType::Ball;
            j.bodyA = ids[static_cast<std::size_t>(a)];
            j.bodyB = ids[static_cast<std::size_t>(b)];
            j.anchor = anchor;
            j.breakForce = breakForce;
            world.createJoint(j);
        };
        const Real weight12 = 12 * Real(9.81);
        for (int k = 0; k < side; ++k) {
            for (int i = 1; i < side; ++i) {
                const int index = k * side + i;
                const auto x = static_cast<Real>(k), y = -static_cast<Real>(i);
                const Real vertical = k % 3 == 1 ? weight12 : std::numeric_limits<Real>::infinity();
                link(index - 1, index, {x, y + Real(0.5), 0}, vertical);
                if (k > 0) link(index - side, index, {x - Real(0.5), y, 0}, std::numeric_limits<Real>::infinity());
            }
        }
        return world;
    };
    const int steps = 30;
    std::vector<std::uint32_t> events;           // (step, joint) pairs, flattened, this configuration's
    std::vector<std::uint32_t> referenceEvents;  // the first configuration's
    const auto recordBreaks = [&](const World& world, int step) {
        for (const JointBreakEvent& e : world.jointBreakEvents()) {
            events.push_back(static_cast<std::uint32_t>(step));
            events.push_back(e.joint.index);
        }
    };
    expectSameBitsForAnyScheduler(build, steps, [&](const World& world, const char* config) {
        if (referenceEvents.empty()) {
            referenceEvents = events;
        } else {
            EXPECT_EQ(events, referenceEvents) << config << ": other break events";
        }
        // Physics check: joints broke, but only vertical ones of the weak
        // columns loaded beyond 12 spheres' weight (the upper rows): each
        // breaking column keeps its lower part, so fewer than side - 12 of
        // its joints break, and at least its top one does.
        const std::size_t broken = events.size() / 2;
        const std::size_t weakColumns = side / 3;
        EXPECT_GE(broken, weakColumns);
        EXPECT_LE(broken, weakColumns * static_cast<std::size_t>(side - 12));
        for (const BodyId id : world.bodies()) ASSERT_TRUE(std::isfinite(world.position(id).y));
        events.clear();
    }, recordBreaks);
}
