// Same input -> bit-identical output, and no heap allocation inside step() once
// the world is built (support/counting_allocator.hpp counts global operator new).
#include <cstring>

#include "dynamics/test_scenes.hpp"
#include "support/counting_allocator.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// A scene touching every force path: gravity, drag, damping, springs, a callback,
// user forces, kinematic and static bodies, tumbling.
void buildScene(World& world) {
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);
    BodyDef k;
    k.type = BodyType::Kinematic;
    k.linearVelocity = {1, 0, 0};
    k.angularVelocity = {0, 1, 0};
    const BodyId kin = world.createBody(k);
    BodyId prev = kin;
    for (int i = 0; i < 20; ++i) {
        BodyDef d;
        d.shape = i % 2 ? Shape::box({Real(0.1), Real(0.2), Real(0.3)}) : Shape::capsule(Real(0.1), Real(0.3));
        d.position = {Real(i) * Real(0.5), 2, 0};
        d.angularVelocity = {Real(0.1) * Real(i), 3, Real(0.2)};
        d.linearDrag = Real(0.1);
        d.quadraticDrag = Real(0.05);
        d.linearDamping = Real(0.01);
        const BodyId b = world.createBody(d);
        SpringDef s;
        s.bodyA = prev;
        s.bodyB = b;
        s.anchorA = world.centerOfMass(prev);
        s.anchorB = d.position;
        s.restLength = Real(0.4);
        s.stiffness = 200;
        s.damping = 1;
        world.createSpring(s);
        prev = b;
        if (i == 5) world.setForceCallback(b, [](const BodyKinematics& kk) { return Wrench{{0, std::sin(kk.time), 0}, {0, 0, Real(0.1)}}; });
    }
}

}  // namespace

TEST(Determinism, SameInputGivesBitIdenticalState) {
    for (Integrator integrator : kAllIntegrators) {
        World a(worldDef(integrator, 4)), b(worldDef(integrator, 4));
        buildScene(a);
        buildScene(b);
        for (int i = 0; i < 120; ++i) {
            a.step(Real(1) / 60);
            b.step(Real(1) / 60);
        }
        const std::vector<BodyId> ia = a.bodies(), ib = b.bodies();
        ASSERT_EQ(ia.size(), ib.size());
        for (std::size_t i = 0; i < ia.size(); ++i) {
            const Transform ta = a.transform(ia[i]), tb = b.transform(ib[i]);
            EXPECT_EQ(std::memcmp(&ta, &tb, sizeof ta), 0) << toString(integrator) << " body " << i;
            const Vec3 va = a.angularVelocity(ia[i]), vb = b.angularVelocity(ib[i]);
            EXPECT_EQ(std::memcmp(&va, &vb, sizeof va), 0);
        }
    }
}

TEST(Allocation, StepDoesNotAllocateInSteadyState) {
    for (Integrator integrator : kAllIntegrators) {
        World world(worldDef(integrator, 4));
        buildScene(world);
        world.step(Real(1) / 60);  // warm-up
        world.applyForce(world.bodies()[3], {1, 0, 0}, {0, 0, 0});
        CountAllocations count;
        for (int i = 0; i < 30; ++i) world.step(Real(1) / 60);
        const EnergyReport e = world.energy();
        const Vec3 l = world.angularMomentum();
        EXPECT_EQ(count.stop(), 0) << toString(integrator);
        EXPECT_TRUE(std::isfinite(e.total) && isFinite(l));
    }
}
