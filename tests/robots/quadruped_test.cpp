// The quadruped of scenes/quadruped.urdf, as scenes/quadruped.json loads it
// (docs/robots.md, "Examples"): built in its standing pose on a ground plane,
// it stands under its eight position drives for 10 s. The torso keeps its
// height and level, every foot stays loaded, and the ground carries the
// robot's weight: the contact forces on the feet sum to m g (statics).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "fulcrum/scene.hpp"
#include "fulcrum/urdf.hpp"
#include "fulcrum/world.hpp"

namespace {

using namespace fulcrum;

const char* const kLegs[] = {"front_left", "front_right", "hind_left", "hind_right"};

Scene quadrupedScene() { return loadScene(std::filesystem::path(FULCRUM_SOURCE_DIR) / "scenes" / "quadruped.json"); }

TEST(Quadruped, LoadsAsTheSceneDescribesIt) {
    const Scene scene = quadrupedScene();
    // The ground, the torso and a thigh and a shin per leg; a hip and a knee per leg.
    EXPECT_EQ(scene.bodies.size(), 1u + 1u + 8u);
    EXPECT_EQ(scene.joints.size(), 8u);
    for (const auto& joint : scene.joints) {
        SCOPED_TRACE(joint.def.name);
        EXPECT_EQ(joint.def.type, JointType::Hinge);
        EXPECT_TRUE(joint.def.spring.enabled);
    }
    World world = buildWorld(scene);
    Real mass = 0;
    for (const BodyId b : world.bodies()) mass += world.mass(b);
    EXPECT_NEAR(mass, 6.6, 1e-5);  // torso 4 kg, thighs 0.4 kg, shins 0.25 kg
}

TEST(Quadruped, StandsUnderItsDrivesCarryingItsWeightOnItsFeet) {
    const Scene scene = quadrupedScene();
    World world = buildWorld(scene);
    const BodyId torso = world.findBody("torso");
    ASSERT_FALSE(torso.isNull());
    std::vector<BodyId> feet;
    for (const char* leg : kLegs) {
        feet.push_back(world.findBody(std::string(leg) + "_shin"));
        ASSERT_FALSE(feet.back().isNull()) << leg;
    }
    Real mass = 0;
    for (const BodyId b : world.bodies()) mass += world.mass(b);
    const Real weight = mass * Real(9.81);
    // Built in the standing pose: each leg 2 x 0.2 m cos 0.5 tall plus the
    // shin capsule's 2 cm radius, the torso 0.2 mm above that.
    const Real standingHeight = world.transform(torso).p.z;
    EXPECT_NEAR(standingHeight, 0.4 * std::cos(0.5) + 0.02, 1e-3);

    const Real dt = scene.dt;
    const int steps = static_cast<int>(std::lround(10 / dt));
    ASSERT_EQ(steps, 1200);
    for (int i = 1; i <= steps; ++i) {
        world.step(dt);
        for (const BodyId b : world.bodies()) {
            const Vec3 p = world.transform(b).p;
            ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << world.name(b) << " at step " << i;
        }
        if (static_cast<Real>(i) * dt < 5) continue;
        // Settled (after 5 s): the torso within 2 cm of its standing height and
        // tilted less than 2 degrees (the drives' sag under 16 N per foot is a
        // few millimetres and the robot is symmetric).
        const Transform t = world.transform(torso);
        ASSERT_NEAR(t.p.z, standingHeight, 0.02) << "at step " << i;
        const Real up = rotate(t.q, Vec3{0, 0, 1}).z;
        ASSERT_GT(up, std::cos(2 * 3.14159265358979 / 180)) << "at step " << i;
        // Every foot on the ground, and together they carry the whole weight.
        const std::vector<Vec3> forces = world.contactForces(feet);
        Real carried = 0;
        for (std::size_t k = 0; k < feet.size(); ++k) {
            ASSERT_GT(forces[k].z, 0.1 * weight) << kLegs[k] << " at step " << i;
            carried += forces[k].z;
        }
        ASSERT_NEAR(carried, weight, 0.02 * weight) << "at step " << i;
    }
}

}  // namespace
