// Shape::bounds of a plain box takes a short path (an unrotated body skips
// the rotation matrix): it must be transformBounds(xf, localBounds()), the
// general path, bit for bit, for any orientation, signed zeros included, and
// body creation's identity fast path in requireOrientation must keep the
// given quaternion's bits too.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "fulcrum/fulcrum.hpp"

namespace fulcrum {
namespace {

bool sameBits(const AABB& a, const AABB& b) { return std::memcmp(&a, &b, sizeof(AABB)) == 0; }

TEST(BoxBounds, ThePlainBoxPathIsTheGeneralOneBitForBit) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<Real> at(-1e4f, 1e4f), half(1e-3f, 50), unit(-1, 1);
    const Quat identities[] = {Quat{1, 0, 0, 0}, Quat{1, -0.0f, 0, -0.0f}, Quat{1, 0, -0.0f, 0}};
    int checked = 0;
    for (int i = 0; i < 3000; ++i) {
        const Shape box = Shape::box({half(rng), half(rng), half(rng)});
        Transform xf{{at(rng), at(rng), at(rng)}, identities[i % 3]};
        if (i % 2 == 1) xf.q = normalize(Quat{unit(rng), unit(rng), unit(rng), unit(rng)});
        if (i % 7 == 0) xf.p = {-0.0f, 0, -0.0f};
        const AABB fast = box.bounds(xf);
        const AABB general = transformBounds(xf, box.localBounds());
        ASSERT_TRUE(sameBits(fast, general)) << "box " << i;
        ++checked;
    }
    EXPECT_EQ(checked, 3000);
}

TEST(BoxBounds, AnIdentityOrientationKeepsItsBitsAtCreation) {
    World world;
    BodyDef d;
    d.type = BodyType::Static;
    d.shape = Shape::box({1, 2, 3});
    d.position = {4, 5, 6};
    d.orientation = Quat{1, -0.0f, 0, -0.0f};
    const BodyId id = world.createBody(d);
    const Quat q = world.orientation(id);
    EXPECT_EQ(std::memcmp(&q, &d.orientation, sizeof(Quat)), 0);
    // A non-unit quaternion is still normalised, and a zero one still named.
    d.orientation = Quat{2, 0, 0, 0};
    EXPECT_EQ(world.orientation(world.createBody(d)).w, Real(1));
    d.orientation = Quat{0, 0, 0, 0};
    try {
        world.createBody(d);
        FAIL() << "a zero quaternion was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("orientation"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace fulcrum
