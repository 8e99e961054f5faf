// Stacks: a 20-box tower, the pyramid20 benchmark scene and a 1:10 mass-ratio
// stack stand (gravity balanced by contact impulses without drift).
#include <gtest/gtest.h>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

WorldDef noSleep() {
    WorldDef d;
    d.sleeping = false;
    return d;
}

struct StackQuality {
    Real drift = 0;  // worst horizontal displacement
    Real sink = 0;   // how far the top box went down
};

StackQuality measure(World& world, const std::vector<BodyId>& boxes, const std::vector<Vec3>& start, BodyId top,
                     Real topStartY) {
    StackQuality q;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        const Vec3 d = world.position(boxes[i]) - start[i];
        q.drift = std::max(q.drift, std::sqrt(d.x * d.x + d.z * d.z));
    }
    q.sink = topStartY - world.position(top).y;
    return q;
}

}  // namespace

// 20 unit boxes stacked exactly touching: after 10 s no box drifted 5 cm and the
// top sank less than 25 cm (soft contacts rest slightly into each other).
TEST(Stacking, TowerOfTwentyBoxesStands) {
    World world(noSleep());
    addGround(world);
    std::vector<BodyId> boxes;
    std::vector<Vec3> start;
    for (int i = 0; i < 20; ++i) {
        boxes.push_back(addBox(world, {0, Real(0.5) + static_cast<Real>(i), 0}));
        start.push_back(world.position(boxes.back()));
    }
    run(world, 600);
    const StackQuality q = measure(world, boxes, start, boxes.back(), start.back().y);
    EXPECT_LT(q.drift, Real(0.05));
    EXPECT_LT(q.sink, Real(0.25));
    EXPECT_GT(q.sink, Real(-0.01));  // and it didn't get pushed up
}

// pyramid20 (bench/scenes.hpp; docs/benchmarks.md): 210 boxes for 10 s with sleeping off.
// Same criteria as the benchmark: drift < 5 cm, top box sink < 25 cm.
TEST(Stacking, Pyramid20Stands) {
    World world(noSleep());
    const BodyId top = buildPyramid(world, 20);
    std::vector<BodyId> boxes;
    std::vector<Vec3> start;
    for (BodyId b : world.bodies()) {
        if (world.bodyType(b) != BodyType::Dynamic) continue;
        boxes.push_back(b);
        start.push_back(world.position(b));
    }
    ASSERT_EQ(boxes.size(), 210u);
    const Real topY = world.position(top).y;
    run(world, 600);
    const StackQuality q = measure(world, boxes, start, top, topY);
    EXPECT_LT(q.drift, Real(0.05));
    EXPECT_LT(q.sink, Real(0.25));
    RecordProperty("drift_mm", std::to_string(q.drift * 1000));
    RecordProperty("sink_mm", std::to_string(q.sink * 1000));
}

// A 10 kg box on a 1 kg box on a 10 kg box... alternating 1:10 masses, 6 high,
// stands for 10 s (drift < 1 cm, sink < 5 cm).
TEST(Stacking, MassRatioOneToTenStands) {
    World world(noSleep());
    addGround(world);
    std::vector<BodyId> boxes;
    std::vector<Vec3> start;
    for (int i = 0; i < 6; ++i) {
        boxes.push_back(addBox(world, {0, Real(0.5) + static_cast<Real>(i), 0}, Vec3::splat(Real(0.5)), i % 2 ? 10 : 1));
        start.push_back(world.position(boxes.back()));
    }
    run(world, 600);
    const StackQuality q = measure(world, boxes, start, boxes.back(), start.back().y);
    EXPECT_LT(q.drift, Real(0.01));
    EXPECT_LT(q.sink, Real(0.05));
}

namespace {

// Boxes of alternating mass on the ground, the bottom one light (1 kg) and
// every other one `heavy` kg, run 10 s with sleeping on. Returns the deepest
// overlap between neighbours (and of the bottom box into the ground) seen at
// the end, the top box's sink and the worst drift.
struct RatioStack {
    Real overlap = 0, sink = 0, drift = 0;
};
RatioStack alternatingStack(int count, Real heavy) {
    World world(WorldDef{});
    addGround(world);
    std::vector<BodyId> boxes;
    for (int i = 0; i < count; ++i) {
        boxes.push_back(addBox(world, {0, Real(0.5) + static_cast<Real>(i), 0}, Vec3::splat(Real(0.5)), i % 2 ? heavy : 1));
    }
    run(world, 600);
    RatioStack r;
    r.overlap = Real(0.5) - world.position(boxes[0]).y;
    for (int i = 0; i + 1 < count; ++i) {
        r.overlap = std::max(r.overlap, 1 - (world.position(boxes[i + 1]).y - world.position(boxes[i]).y));
    }
    for (BodyId b : boxes) r.drift = std::max(r.drift, std::hypot(world.position(b).x, world.position(b).z));
    r.sink = Real(0.5) + static_cast<Real>(count - 1) - world.position(boxes.back()).y;
    return r;
}

}  // namespace

// The mass ratios docs/solver.md ("Mass ratios") says the soft contacts hold:
// a box 300x heavier on a light one rests ~3 cm into it (a soft contact is a
// spring of stiffness m omega^2 for the light body's mass m, so the overlap
// grows with the ratio: 1 cm at 1:100), and an alternating 1:100 stack of five
// rests ~2 cm per contact. Beyond (1:500 and 1:200), the heavy boxes sink
// through: World::deepOverlaps and the CLI's summary say so.
TEST(Stacking, HeavyOnLightHoldsToOneToThreeHundred) {
    const RatioStack r = alternatingStack(2, 300);
    EXPECT_LT(r.overlap, Real(0.04));
    EXPECT_LT(r.sink, Real(0.06));
    EXPECT_LT(r.drift, Real(0.01));
}

TEST(Stacking, AlternatingOneToHundredStackOfFiveStands) {
    const RatioStack r = alternatingStack(5, 100);
    EXPECT_LT(r.overlap, Real(0.03));
    EXPECT_LT(r.sink, Real(0.07));
    EXPECT_LT(r.drift, Real(0.03));
}
