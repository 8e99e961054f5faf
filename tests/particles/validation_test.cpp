// Bad input at the particle API boundary: fulcrum::Error naming the system and
// the field, saying what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "particles/particle_builders.hpp"
#include "particles/particle_world.hpp"
#include "rigid_test_world.hpp"
#include "support/error_of.hpp"

using namespace fulcrum;
using fulcrum::test::errorOf;

namespace {

#define EXPECT_ERROR(expr, ...)                                                    \
    do {                                                                           \
        const std::string message = errorOf([&] { (void)(expr); });                \
        for (const char* part : {__VA_ARGS__}) EXPECT_NE(message.find(part), std::string::npos) << message; \
    } while (0)

RopeDef rope() {
    RopeDef d;
    d.name = "r1";
    return d;
}
ClothDef cloth() {
    ClothDef d;
    d.name = "c1";
    return d;
}
constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
constexpr Real kInf = std::numeric_limits<Real>::infinity();

}  // namespace

TEST(Validation, RopeBadInputs) {
    RopeDef d = rope();
    d.segments = 0;
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "segments", "at least 1", "got 0");
    d.segments = 1000000000;  // was a std::bad_alloc (or the OOM killer), not an Error
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "segments", "must be below 100000000", "got 1000000000");
    d = rope();
    d.end = d.start;
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "end", "coincides with start", "spacing must be positive");
    d = rope();
    d.particleMass = 0;
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "particle_mass", "must be positive", "got 0");
    d = rope();
    d.particleMass = -1;
    EXPECT_ERROR(buildRope(d), "particle_mass", "got -1");
    d = rope();
    d.radius = 0;
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "radius", "must be positive");
    d = rope();
    d.start = {kNaN, 0, 0};
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "start", "must be finite");
    d = rope();
    d.end = {0, kInf, 0};
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "end", "must be finite");
    d = rope();
    d.stretchCompliance = -1e-3f;
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "stretch_compliance", "must not be negative");
    d = rope();
    d.bendCompliance = kNaN;
    EXPECT_ERROR(buildRope(d), "rope 'r1'", "bend_compliance", "finite");
}

TEST(Validation, ClothBadInputs) {
    ClothDef d = cloth();
    d.spacing = 0;
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "spacing", "must be positive", "got 0");
    d = cloth();
    d.spacing = -0.1f;
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "spacing", "got -0.1");
    d = cloth();
    d.size = {1, 16};
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "size[0]", "at least 2", "got 1");
    d = cloth();
    d.size = {16, 0};
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "size[1]", "got 0");
    d = cloth();
    d.particleMass = -2;
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "particle_mass", "must be positive");
    d = cloth();
    d.radius = -1;
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "radius", "must be positive");
    d = cloth();
    d.pinned = {{0, 0}, {16, 3}};
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "pinned[1]", "[16, 3]", "outside the 16 x 16 grid");
    d = cloth();
    d.pinned = {{-1, 0}};
    EXPECT_ERROR(buildCloth(d), "pinned[0]", "[-1, 0]", "outside");
    d = cloth();
    d.uAxis = {0, 0, 0};
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "u_axis", "zero vector");
    d = cloth();
    d.vAxis = {0, 0, 0};
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "v_axis", "zero vector");
    d = cloth();
    d.vAxis = {-2, 0, 0};
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "v_axis", "parallel to u_axis");
    d = cloth();
    d.origin = {0, kNaN, 0};
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "origin", "must be finite");
    d = cloth();
    d.uAxis = {kInf, 0, 0};
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "u_axis", "must be finite");
    d = cloth();
    d.stretchCompliance = -1;
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "stretch_compliance", "must not be negative");
    d = cloth();
    d.bendCompliance = -1;
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "bend_compliance", "must not be negative");
    d = cloth();
    d.shearCompliance = -1;
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "shear_compliance", "must not be negative");
    d = cloth();
    d.spacing = kNaN;
    EXPECT_ERROR(buildCloth(d), "cloth 'c1'", "spacing", "finite");
}

TEST(Validation, AttachmentsAndWorld) {
    test_support::TestRigidWorld rigid;
    rigid.addStatic(Shape::plane({0, 1, 0}, 0));
    ParticleWorld world;
    RopeDef d = rope();
    d.attachEnd = BodyId{7, 0};
    EXPECT_ERROR(world.addRope(d, &rigid), "rope 'r1'", "attach_end", "unknown body index 7");
    EXPECT_ERROR(world.addRope(d), "rope 'r1'", "attach_end", "no rigid world");
    d = rope();
    d.attachStart = BodyId{3, 0};
    EXPECT_ERROR(world.addRope(d, &rigid), "attach_start", "unknown body index 3");
    EXPECT_EQ(world.systemCount(), 0u);  // nothing half-added

    world.addRope(rope());
    EXPECT_ERROR(world.addRope(rope()), "rope 'r1'", "name", "already used");
    EXPECT_ERROR(world.step(0), "dt", "positive");
    EXPECT_ERROR(world.step(kNaN), "dt");
    ParticleWorldSettings s;
    s.substeps = 0;
    EXPECT_ERROR(world.setSettings(s), "substeps", "at least 1");
    s = {};
    s.iterations = -1;
    EXPECT_ERROR(world.setSettings(s), "iterations", "at least 1");
    s = {};
    s.gravity = {0, kNaN, 0};
    EXPECT_ERROR(world.setSettings(s), "gravity", "finite");

    ParticleSystem sys = buildRope(rope());
    EXPECT_ERROR(setParticleMass(sys, 99, 1), "rope 'r1'", "particle 99", "11 particles");
    EXPECT_ERROR(setParticleMass(sys, 1, -1), "rope 'r1'", "particle_mass", "positive");
    EXPECT_ERROR(pinParticle(sys, 11), "rope 'r1'", "pinned", "particle 11");
    EXPECT_ERROR(addParticleSpring(sys, {0, 0, 1, 1, 0}), "spring", "itself");
    EXPECT_ERROR(addParticleSpring(sys, {0, 1, 1, -5, 0}), "spring.stiffness", "must not be negative");

    ParticleSystemId stale = world.systems().front();
    world.remove(stale);
    EXPECT_ERROR(world.system(stale), "stale");
    EXPECT_ERROR(world.system(ParticleSystemId{}), "null");
}
