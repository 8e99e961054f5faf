// A compound's local bounds are formed once with its children (Shape::
// setChildren) where every call formed them again: they must be the union of
// the children's bounds at their transforms, bit for bit, for compounds of
// every convex kind (rounded hulls among them), nested compounds, and a
// compound a snapshot restores.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "fulcrum/snapshot.hpp"

namespace fulcrum {
namespace {

bool sameBits(const AABB& a, const AABB& b) { return std::memcmp(&a, &b, sizeof(AABB)) == 0; }

AABB childrenUnion(const Shape& compound) {
    AABB b;
    for (const CompoundChild& c : compound.children()) b.grow(c.shape.bounds(c.transform));
    return b;
}

Shape randomCompound(std::mt19937& rng, int depth) {
    std::uniform_real_distribution<Real> at(-5, 5), size(Real(0.05), 2), unit(-1, 1);
    std::vector<CompoundChild> children;
    const int count = 1 + static_cast<int>(rng() % 23);
    for (int i = 0; i < count; ++i) {
        Shape s;
        switch (rng() % (depth > 0 ? 6 : 5)) {
            case 0: s = Shape::sphere(size(rng)); break;
            case 1: s = Shape::box({size(rng), size(rng), size(rng)}); break;
            case 2: s = Shape::capsule(size(rng), size(rng)); break;
            case 3: s = Shape::cylinder(size(rng), size(rng)); break;
            case 4: {
                std::vector<Vec3> points;
                for (int k = 0; k < 12; ++k) points.push_back({at(rng), at(rng), at(rng)});
                s = Shape::convexHull(points);
                break;
            }
            default: s = randomCompound(rng, depth - 1); break;
        }
        const Quat q = i % 3 == 0 ? Quat{} : normalize(Quat{unit(rng), unit(rng), unit(rng), unit(rng)});
        children.push_back({s, Transform{{at(rng), at(rng), at(rng)}, q}});
    }
    return Shape::compound(children);
}

TEST(CompoundBounds, LocalBoundsAreTheChildrensUnionBitForBit) {
    std::mt19937 rng(13);
    for (int i = 0; i < 300; ++i) {
        const Shape compound = randomCompound(rng, 2);
        ASSERT_TRUE(sameBits(compound.localBounds(), childrenUnion(compound))) << "compound " << i;
        const Shape copy = compound;  // a copy keeps them
        ASSERT_TRUE(sameBits(copy.localBounds(), childrenUnion(compound))) << "compound " << i;
    }
}

TEST(CompoundBounds, ASnapshotsCompoundHasItsChildrensUnion) {
    std::mt19937 rng(17);
    World world;
    std::vector<BodyId> ids;
    for (int i = 0; i < 20; ++i) {
        BodyDef d;
        d.shape = randomCompound(rng, 1);
        d.position = {Real(20 * i), 10, 0};
        ids.push_back(world.createBody(d));
    }
    const World loaded = loadSnapshotFromMemory(saveSnapshotToMemory(world));
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const Shape& shape = loaded.shape(ids[i]);
        ASSERT_EQ(shape.type(), ShapeType::Compound);
        EXPECT_TRUE(sameBits(shape.localBounds(), childrenUnion(shape))) << "body " << i;
        EXPECT_TRUE(sameBits(shape.localBounds(), world.shape(ids[i]).localBounds())) << "body " << i;
    }
}

}  // namespace
}  // namespace fulcrum
