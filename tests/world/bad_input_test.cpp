// Bad input found by the hunt of issue 26 ("Bad input, everywhere"): each case
// used to crash, exhaust memory or report the wrong cause; now it is refused at
// the door with a message naming the setting (docs/reliability.md).
#include <gmock/gmock.h>

#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "fulcrum/snapshot.hpp"
#include "support/error_of.hpp"

using namespace fulcrum;
using namespace fulcrum::test;
using ::testing::AllOf;
using ::testing::HasSubstr;

namespace {

// A sphere wrapped in `levels` compounds, each built through Shape::compound.
Shape nestedCompound(int levels) {
    Shape s = Shape::sphere(Real(0.5));
    for (int i = 0; i < levels; ++i) {
        const CompoundChild child{s, Transform{}};
        s = Shape::compound(std::span<const CompoundChild>(&child, 1));
    }
    return s;
}

}  // namespace

// substeps = 1e9 used to build a stage list that ran out of memory and was
// reported as too many contact pairs; 1e6 threads tried to start them all.
TEST(WorldBadInput, WorldCountsHaveUpperLimits) {
    WorldDef d;
    d.substeps = 1000000000;
    EXPECT_EQ(errorOf([&] { World w(d); }), "world: substeps must be at most 1000, got 1000000000");
    d = {};
    d.solverIterations = kMaxSolverIterations + 1;
    EXPECT_EQ(errorOf([&] { World w(d); }), "world: solverIterations must be at most 1000, got 1001");
    d = {};
    d.threads = 1000000;
    EXPECT_EQ(errorOf([&] { World w(d); }), "world: threads must be at most 1024, got 1000000");

    World world;
    EXPECT_THAT(errorOf([&] { world.setSubsteps(kMaxSubsteps + 1); }), HasSubstr("substeps must be at most"));
    EXPECT_THAT(errorOf([&] { world.setSolverIterations(1 << 30); }), HasSubstr("solverIterations must be at most"));
    EXPECT_THAT(errorOf([&] { world.setThreadCount(kMaxThreads + 1); }), HasSubstr("threads must be at most"));
    EXPECT_EQ(world.settings().substeps, WorldDef{}.substeps);  // a refused setting changes nothing

    // The limits themselves are valid.
    d = {};
    d.substeps = kMaxSubsteps;
    d.solverIterations = kMaxSolverIterations;
    World busy(d);
    BodyDef ball;
    ball.shape = Shape::sphere(Real(0.5));
    busy.createBody(ball);
    busy.step(Real(1) / 60);
    EXPECT_EQ(busy.stepCount(), 1u);
}

// A compound nested 100,000 deep (easy to build in a loop) overflowed the stack
// in the recursive shape code: a segfault at createBody.
TEST(WorldBadInput, CompoundNestingIsLimited) {
    const Shape deepest = nestedCompound(kMaxCompoundLevels);
    const CompoundChild child{deepest, Transform{}};
    EXPECT_EQ(errorOf([&] { Shape::compound(std::span<const CompoundChild>(&child, 1)); }),
              "compound: children[0] makes compounds nested deeper than 32 levels");

    // The deepest allowed compound is a body, and it survives a snapshot (whose
    // reader holds the same limit).
    World world;
    BodyDef d;
    d.shape = deepest;
    world.createBody(d);
    world.step(Real(1) / 60);
    World copy = loadSnapshotFromMemory(saveSnapshotToMemory(world));
    copy.step(Real(1) / 60);
    EXPECT_EQ(copy.bodyCount(), 1u);
}
