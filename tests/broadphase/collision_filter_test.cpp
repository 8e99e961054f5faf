// Truth table of shouldCollide against the semantics stated in body.hpp:
// collide when (A.category & B.mask) and (B.category & A.mask) are both
// non-zero, unless the two share a non-zero group: positive always collides,
// negative never does.
#include <gtest/gtest.h>

#include "collision/collision_filter.hpp"

namespace fulcrum {
namespace {

CollisionFilter make(std::uint32_t category, std::uint32_t mask, std::int32_t group = 0) {
    CollisionFilter f;
    f.category = category;
    f.mask = mask;
    f.group = group;
    return f;
}

TEST(CollisionFilter, DefaultsCollide) { EXPECT_TRUE(shouldCollide(CollisionFilter{}, CollisionFilter{})); }

TEST(CollisionFilter, CategoryAndMaskMustAgreeBothWays) {
    const CollisionFilter player = make(0b0001, 0b1110);   // hits everything but players
    const CollisionFilter enemy = make(0b0010, 0b1111);
    const CollisionFilter ghost = make(0b0100, 0b0000);    // accepts nothing
    const CollisionFilter debris = make(0b1000, 0b0010);   // only hits enemies
    EXPECT_FALSE(shouldCollide(player, player));            // player's mask excludes players
    EXPECT_TRUE(shouldCollide(player, enemy));
    EXPECT_FALSE(shouldCollide(player, ghost));             // ghost's mask rejects the player
    EXPECT_FALSE(shouldCollide(ghost, player));
    EXPECT_FALSE(shouldCollide(player, debris));            // player accepts debris, debris rejects player
    EXPECT_FALSE(shouldCollide(debris, player));
    EXPECT_TRUE(shouldCollide(enemy, debris));
    EXPECT_TRUE(shouldCollide(debris, enemy));
}

TEST(CollisionFilter, SharedPositiveGroupAlwaysCollides) {
    // Masks that reject each other, overridden by the shared positive group.
    EXPECT_TRUE(shouldCollide(make(1, 0, 3), make(2, 0, 3)));
}

TEST(CollisionFilter, SharedNegativeGroupNeverCollides) {
    // Masks that accept each other, overridden by the shared negative group
    // (e.g. the links of one ragdoll).
    EXPECT_FALSE(shouldCollide(make(1, ~0u, -2), make(1, ~0u, -2)));
}

TEST(CollisionFilter, DifferentOrZeroGroupsFallBackToMasks) {
    EXPECT_TRUE(shouldCollide(make(1, ~0u, -2), make(1, ~0u, -3)));   // different negative groups
    EXPECT_FALSE(shouldCollide(make(1, 2, 4), make(1, 2, 5)));        // different positive groups, masks reject
    EXPECT_TRUE(shouldCollide(make(1, 1, -1), make(1, 1, 1)));        // opposite signs: masks decide
    EXPECT_FALSE(shouldCollide(make(1, 2, 0), make(1, 2, 0)));        // group 0 is "no group"
}

TEST(CollisionFilter, ExhaustiveSmallTableMatchesDefinitionAndIsSymmetric) {
    // Every combination of 2-bit categories and masks and groups in {-1, 0, 1}.
    for (std::uint32_t ca = 0; ca < 4; ++ca)
        for (std::uint32_t ma = 0; ma < 4; ++ma)
            for (std::uint32_t cb = 0; cb < 4; ++cb)
                for (std::uint32_t mb = 0; mb < 4; ++mb)
                    for (int ga = -1; ga <= 1; ++ga)
                        for (int gb = -1; gb <= 1; ++gb) {
                            const CollisionFilter a = make(ca, ma, ga), b = make(cb, mb, gb);
                            bool expected = (ca & mb) != 0 && (cb & ma) != 0;
                            if (ga == gb && ga != 0) expected = ga > 0;
                            ASSERT_EQ(shouldCollide(a, b), expected) << ca << ma << cb << mb << ga << gb;
                            ASSERT_EQ(shouldCollide(a, b), shouldCollide(b, a));
                        }
}

}  // namespace
}  // namespace fulcrum
