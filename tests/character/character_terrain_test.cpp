// The character on heightfield terrain (docs/characters.md): walking up a
// field's slope is decided by its triangles' normals as on any other ground,
// walkable under max_slope and a wall above it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <fulcrum/fulcrum.hpp>

namespace {

using namespace fulcrum;

constexpr Real kDt = Real(1) / Real(60);
constexpr Real kHeight = Real(1.8);

// Feet height after `seconds` walking at 2 m/s along +x, from x = 0, towards
// a heightfield that is flat up to x = 1 and then rises at `slope`.
Real climbHeightField(Real slope, Real seconds) {
    World world;
    constexpr Real kSpacing = Real(0.25), kX0 = -2, kFoot = 1;
    constexpr std::uint32_t kColumns = 57, kRows = 25;  // x in [-2, 12], z in [-3, 3]
    std::vector<Real> heights(kRows * kColumns);
    const Real rise = std::tan(slope);
    for (std::uint32_t r = 0; r < kRows; ++r) {
        for (std::uint32_t c = 0; c < kColumns; ++c) {
            heights[r * kColumns + c] = std::max(Real(0), kX0 + Real(c) * kSpacing - kFoot) * rise;
        }
    }
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::heightField(kRows, kColumns, kSpacing, kSpacing, heights);
    ground.position = {kX0, 0, -3};
    world.createBody(ground);
    CharacterDef def;
    def.name = "walker";
    def.position = {0, kHeight / 2 + Real(0.01), 0};
    def.height = kHeight;
    def.maxSlope = Real(std::numbers::pi / 4);
    def.inputs = {{0, {2, 0, 0}, false}};
    const CharacterId c = world.createCharacter(def);
    for (int i = 0; i < int(seconds / kDt); ++i) world.step(kDt);
    return world.characterState(c).position.y - kHeight / 2;
}

TEST(CharacterTerrain, WalksUpThirtyDegreeHeightFieldNotFifty) {
    // As Character.WalksUpThirtyDegreesNotFifty, on a heightfield: 4 s at
    // 2 m/s climbs metres up 30 degrees (max slope 45) and stops at the foot
    // of 50 degrees.
    const Real up30 = climbHeightField(Real(30 * std::numbers::pi / 180), 4);
    const Real up50 = climbHeightField(Real(50 * std::numbers::pi / 180), 4);
    std::printf("feet after 4 s: %.3f m up the 30 degree field, %.3f m at the 50 degree one\n", double(up30), double(up50));
    EXPECT_GT(up30, Real(2.0));
    EXPECT_LT(up50, Real(0.1));
}

}  // namespace
