// Bodies a kinematic pusher drives into one another must keep the whole
// push-out speed (docs/solver.md, "Born deep, driven deep"): the junkyard's
// pusher jammed rocks 0.9 m into each other while they shared it.
#include <gtest/gtest.h>

#include <algorithm>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

struct Jam {
    Real deepestLastSecond = 0;  // m: the deepest contact over the last 60 steps
    Real sledgeSpeed = 0;        // m/s: its mean over the last second
};

// A kinematic plate speeds up over 1 s to 3.5 m/s (no impact) and pushes
// `boxes` unit boxes of 1 kg in a row into a 150 kg box, all on a floor of
// friction 0.6: the row carries the sledge's 880 N of friction. 180 steps.
Jam pushRowIntoSledge(int boxes) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    addGround(world);
    BodyDef plate;
    plate.type = BodyType::Kinematic;
    plate.shape = Shape::box({Real(0.25), Real(0.5), Real(0.5)});
    plate.position = {Real(-0.75), Real(0.5), 0};
    const BodyId pusher = world.createBody(plate);
    for (int i = 0; i < boxes; ++i) addBox(world, {Real(0.5) + static_cast<Real>(i), Real(0.5), 0});
    const BodyId sledge = addBox(world, {Real(0.5) + static_cast<Real>(boxes), Real(0.5), 0}, Vec3::splat(Real(0.5)), 150);
    const Real speed = Real(3.5);
    Jam jam;
    Real sledgeFrom = 0;
    for (int s = 0; s < 180; ++s) {
        world.setLinearVelocity(pusher, {speed * std::min(Real(1), static_cast<Real>(s) / 60), 0, 0});
        world.step(kDt);
        if (s == 119) sledgeFrom = world.position(sledge).x;
        if (s < 120) continue;
        for (const ContactReport& r : world.contacts()) jam.deepestLastSecond = std::max(jam.deepestLastSecond, r.depth);
    }
    jam.sledgeSpeed = world.position(sledge).x - sledgeFrom;  // over 60 steps: 1 s
    return jam;
}

}  // namespace

// One box between the plate and the sledge has one deep contact of its own
// and rests 1.2 cm deep at the steady push. Three boxes in a row have two deep
// contacts each; while deep overlaps shared the push-out speed, each got half
// of it, went deeper and locked: 55 cm in the last second, the middle boxes
// inside each other. Asked: below 15 cm (measured: 8.9 cm) and the sledge
// pushed along at the plate's speed (its mean over that second, within 5 %).
TEST(PusherJam, BoxesDrivenIntoEachOtherKeepTheWholePushOut) {
    const Jam single = pushRowIntoSledge(1);
    const Jam row = pushRowIntoSledge(3);
    EXPECT_LT(single.deepestLastSecond, Real(0.03));
    EXPECT_LT(row.deepestLastSecond, Real(0.15));
    EXPECT_NEAR(row.sledgeSpeed, Real(3.5), Real(0.175));
    RecordProperty("single_deepest", std::to_string(single.deepestLastSecond));
    RecordProperty("row_deepest", std::to_string(row.deepestLastSecond));
}
