// No heap allocation per step in steady state with bodies resting on a
// heightfield, awake (the per-triangle contact scratch, the mip-map walk's
// fixed stack), and a rope draped on it (the closest-point search). While the
// bodies still roll, a contact touching more triangles than any before grows
// the shared contact scratch once, as on a mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fulcrum/world.hpp"
#include "support/counting_allocator.hpp"

using namespace fulcrum;

TEST(Allocation, BodiesOnAHeightFieldAllocateNothingInSteadyState) {
    WorldDef def;
    def.sleeping = false;  // keep every pair in the narrow phase
    World world(def);
    std::vector<Real> heights;
    for (int r = 0; r < 41; ++r) {
        for (int c = 0; c < 41; ++c) {
            heights.push_back(Real(0.4) * std::sin(Real(0.3) * static_cast<Real>(c)) * std::cos(Real(0.25) * static_cast<Real>(r)));
        }
    }
    BodyDef field;
    field.type = BodyType::Static;
    field.shape = Shape::heightField(41, 41, Real(0.5), Real(0.5), heights, std::vector<std::uint32_t>{820});
    field.position = {-10, 0, -10};
    world.createBody(field);
    for (int i = 0; i < 30; ++i) {
        BodyDef d;
        d.shape = (i % 2 == 0) ? Shape::sphere(Real(0.3)) : Shape::box(Vec3::splat(Real(0.25)));
        d.mass = 1;
        d.position = {static_cast<Real>(i % 6) * 3 - 7, 2, static_cast<Real>(i / 6) * 3 - 6};
        d.linearDamping = Real(0.3);
        world.createBody(d);
    }
    RopeDef rope;
    rope.start = {-3, 3, 3};
    rope.end = {3, 3, 3};
    rope.segments = 16;
    world.createRope(rope);
    // Warm-up: the bodies roll into the valleys and settle (kept awake), every buffer reaches its size.
    for (int i = 0; i < 480; ++i) world.step(Real(1) / 60);
    test::CountAllocations count;
    for (int i = 0; i < 120; ++i) world.step(Real(1) / 60);
    EXPECT_EQ(count.stop(), 0);
    EXPECT_GT(world.contacts().size(), 0u);
}
