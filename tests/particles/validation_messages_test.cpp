// The particle systems check their input with the same library as bodies,
// joints and springs (dynamics/validation.hpp), so their messages read alike:
// "<subject>: <field> <what is wrong>, got <value>", vectors as (x, y, z).
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "dynamics/validation.hpp"
#include "particles/particle_builders.hpp"
#include "support/error_of.hpp"

using namespace fulcrum;
using fulcrum::test::errorOf;

namespace {

constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();

}  // namespace

TEST(ValidationMessages, ParticleSystemsUseTheSharedWording) {
    RopeDef rope;
    rope.name = "r1";
    rope.start = {kNaN, 0, 0};
    EXPECT_EQ(errorOf([&] { (void)buildRope(rope); }), "rope 'r1': start must be finite, got (nan, 0, 0)");
    rope = {};
    rope.radius = kNaN;
    EXPECT_EQ(errorOf([&] { (void)buildRope(rope); }), "rope (unnamed): radius must be finite, got nan");
    rope = {};
    rope.name = "r1";
    rope.particleMass = -1;
    EXPECT_EQ(errorOf([&] { (void)buildRope(rope); }), "rope 'r1': particle_mass must be positive, got -1");
}

TEST(ValidationMessages, SubjectsSpellTheObject) {
    EXPECT_EQ(detail::Subject("body", "crate", 3).describe(), "body 'crate'");
    EXPECT_EQ(detail::Subject("body", "", 3).describe(), "body #3");
    EXPECT_EQ(detail::Subject("world").describe(), "world");
    const std::string label = detail::particleSystemLabel("cloth", "");
    EXPECT_EQ(detail::Subject(label).describe(), "cloth (unnamed)");
    EXPECT_EQ(errorOf([&] { detail::requirePositive(label, "spacing", 0); }), "cloth (unnamed): spacing must be positive, got 0");
    EXPECT_EQ(errorOf([&] { detail::requireFinite(detail::Subject("spring", "", 2), "anchorA", Vec3(0, kNaN, 0)); }),
              "spring #2: anchorA must be finite, got (0, nan, 0)");
}
