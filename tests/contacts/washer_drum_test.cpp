// Box3D's washer, small (bench/churn_scenes.hpp: washer(6), 216 cubes of
// 0.4 m in the kinematic drum turning at 25 degrees/s): the drum's contacts
// must hold the cubes at a resting depth while they land on its wall and
// tumble. A kinematic body yields to nothing, so a contact point the narrow
// phase puts in the wrong place shows here: a point 3.9 m from its cube (the
// midpoint of the cube's corner and the far end of a 20 m wall face) spun the
// cube, and the drum's deepest contact read 11.8 cm (16.5 cm in washer(8));
// measured after the fix: 1.6 cm (washer(8): 1.8 cm). The cubes land at up
// to 12 m/s, which the speculative contacts and four sub-steps stop within
// a few centimetres. Bound: 3 cm. And no cube leaves the drum through its
// wall: every cube ends inside radius 16 m of the drum's axis or has fallen
// out of an open end (|z| > 10 m) onto the ground.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../../bench/churn_scenes.hpp"
#include "../../bench/fulcrum_world.hpp"

using namespace fulcrum;

TEST(WasherDrum, KinematicDrumHoldsItsCubesAtARestingDepth) {
    const bench::SceneSpec scene = bench::washer(6, 240);
    bench::FulcrumWorld built = bench::buildFulcrumWorld(scene, 1);
    World& world = *built.world;
    const BodyId drum = built.bodies[1];
    ASSERT_TRUE(scene.bodies[1].isKinematic);
    Real deepestWithDrum = 0;
    for (int i = 0; i < scene.steps; ++i) {
        world.step(Real(scene.dt));
        for (const ContactReport& c : world.contacts()) {
            if (c.bodyA == drum || c.bodyB == drum) deepestWithDrum = std::max(deepestWithDrum, c.depth);
        }
    }
    EXPECT_LT(deepestWithDrum, Real(0.03));
    const Vec3 axis = world.position(drum);
    for (std::size_t i = 2; i < built.bodies.size(); ++i) {
        const Vec3 p = world.position(built.bodies[i]);
        const Real radial = std::hypot(p.x - axis.x, p.y - axis.y);
        EXPECT_TRUE(radial < 16 || std::fabs(p.z) > 10) << "cube " << i << " at radial " << radial << ", z " << p.z;
    }
    RecordProperty("deepest_with_drum", std::to_string(deepestWithDrum));
}
