// Snapshot format version 13: each contact's piece poses (piece recycling
// against a static mesh; contact.hpp, PiecePose). They decide which pieces
// the next narrow phase skips, so a world saved with them resumes bit for
// bit, and one whose poses are dropped (a version-12 file) collides every
// piece once and goes its own way.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"
#include "world/snapshot_versions.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {
namespace {

constexpr Real kDt = Real(1) / 60;

// Hex prisms, boxes and a two-hull compound landing on a gentle wave mesh
// of 0.5 m cells and sliding to rest.
World piecesOnWaves() {
    World world(WorldDef{});
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    constexpr int kCells = 24;
    for (int i = 0; i <= kCells; ++i) {
        for (int j = 0; j <= kCells; ++j) {
            const Real x = Real(0.5) * Real(i) - 6, z = Real(0.5) * Real(j) - 6;
            vertices.push_back({x, Real(0.1) * std::sin(Real(0.5) * x) * std::cos(Real(0.4) * z), z});
        }
    }
    const auto at = [](int i, int j) { return static_cast<std::uint32_t>(i * (kCells + 1) + j); };
    for (int i = 0; i < kCells; ++i) {
        for (int j = 0; j < kCells; ++j) {
            triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            triangles.push_back({at(i + 1, j + 1), at(i + 1, j), at(i, j)});
        }
    }
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::mesh(vertices, triangles);
    world.createBody(ground);
    std::vector<Vec3> prism;
    for (int k = 0; k < 6; ++k) {
        const Real a = Real(k) * Real(3.14159265358979 / 3);
        for (const Real z : {Real(-1), Real(1)}) prism.push_back({Real(0.3) * std::cos(a), Real(0.3) * std::sin(a), z});
    }
    const Shape log = Shape::convexHull(prism);
    std::vector<CompoundChild> children;
    children.push_back({log, Transform{Vec3{0, 0, Real(-0.9)}, Quat{}}});
    children.push_back({Shape::box({Real(0.3), Real(0.3), Real(0.3)}), Transform{Vec3{0, 0, Real(1.3)}, Quat{}}});
    const Shape compound = Shape::compound(children);
    for (int i = 0; i < 6; ++i) {
        BodyDef d;
        d.shape = i % 3 == 2 ? Shape::box({Real(0.4), Real(0.25), Real(0.5)}) : (i % 3 == 1 ? compound : log);
        d.position = {Real(1.7) * Real(i) - 4, Real(0.6) + Real(0.2) * Real(i % 2), Real(0.9) * Real(i % 3) - 1};
        d.orientation = Quat::fromAxisAngle(Vec3{1, 0, 0}, Real(0.05) * Real(i));
        d.linearVelocity = {Real(0.6), 0, Real(-0.3)};
        world.createBody(d);
    }
    return world;
}

std::size_t poseCount(const World& world) {
    std::size_t n = 0;
    for (const detail::Contact& c : detail::implOf(world).contactManager.contacts()) n += c.alive ? c.piecePoses.size() : 0;
    return n;
}

TEST(PieceRecyclingSnapshot, MeshContactsResumeBitForBitWithTheirPiecePoses) {
    // Saved at several moments of the landing and sliding: each resumes bit
    // for bit; a version-12 file (no poses: every piece is collided once)
    // must go its own way from at least one of them.
    bool twelveDiverged = false;
    for (const int saveAt : {20, 35, 50, 65, 80}) {
        World original = piecesOnWaves();
        for (int i = 0; i < saveAt; ++i) original.step(kDt);
        const std::size_t poses = poseCount(original);
        ASSERT_GT(poses, 5u) << "the pieces must be on the mesh, with poses";
        const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(original);
        EXPECT_EQ(bytes[8], kSnapshotVersion);
        World resumed = loadSnapshotFromMemory(bytes);
        EXPECT_EQ(poseCount(resumed), poses);
        World fromTwelve = loadSnapshotFromMemory(detail::saveSnapshotAsVersion(original, 12));
        EXPECT_EQ(poseCount(fromTwelve), 0u);
        for (int i = 0; i < 60; ++i) {
            original.step(kDt);
            resumed.step(kDt);
            fromTwelve.step(kDt);
            ASSERT_EQ(test::stateHash(resumed), test::stateHash(original)) << "saved at " << saveAt << ", diverged at step " << i + 1;
            twelveDiverged = twelveDiverged || test::stateHash(fromTwelve) != test::stateHash(original);
        }
        EXPECT_GT(detail::implOf(original).contactManager.recycledPieceCount(), 0u);
    }
    EXPECT_TRUE(twelveDiverged) << "the poses must matter in this scene";
}

// The poses are each contact's own, written by whichever worker collides the
// pair: the same bits on one thread as on three.
TEST(PieceRecyclingSnapshot, TheRecycledRunIsTheSameOnAnyThreadCount) {
    World one = piecesOnWaves();
    World three = piecesOnWaves();
    one.setThreadCount(1);
    three.setThreadCount(3);
    for (int i = 0; i < 150; ++i) {
        one.step(kDt);
        three.step(kDt);
        ASSERT_EQ(test::stateHash(three), test::stateHash(one)) << "diverged at step " << i + 1;
    }
    EXPECT_GT(detail::implOf(one).contactManager.recycledPieceCount(), 0u);
}

}  // namespace
}  // namespace fulcrum
