// Snapshot format version 12: each contact's GJK warm start (two hulls;
// collision/manifold.hpp, GjkWarmStart). Where a hull pair's GJK starts
// changes its answer in the last bits, so a world saved with the starts
// resumes bit for bit, and one whose starts are dropped (a version-11 file)
// goes its own way.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
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

// Twenty-four rocks (hulls of 20 points, three shapes) dropped in a heap on a box ground.
World rockHeap() {
    World world(WorldDef{});
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({20, 1, 20});
    ground.position = {0, -1, 0};
    world.createBody(ground);
    std::mt19937 rng(7);
    std::normal_distribution<Real> g(0, 1);
    std::vector<Shape> rocks;
    for (int k = 0; k < 3; ++k) {
        std::vector<Vec3> points;
        for (int i = 0; i < 20; ++i) {
            const Vec3 d = normalize(Vec3{g(rng), g(rng), g(rng)});
            points.push_back({d.x * Real(0.6), d.y * Real(0.4), d.z * Real(0.5)});
        }
        rocks.push_back(Shape::convexHull(points));
    }
    for (int i = 0; i < 24; ++i) {
        BodyDef d;
        d.shape = rocks[static_cast<std::size_t>(i % 3)];
        d.position = {Real(0.9) * Real(i % 3) - Real(0.9), Real(0.6) + Real(0.7) * Real(i / 3), Real(0.9) * Real((i / 3) % 2) - Real(0.4)};
        d.orientation = Quat::fromAxisAngle(normalize(Vec3{Real(0.3), 1, Real(0.1) * Real(i)}), Real(0.5) * Real(i));
        world.createBody(d);
    }
    return world;
}

std::size_t warmStarts(const World& world) {
    std::size_t n = 0;
    for (const detail::Contact& c : detail::implOf(world).contactManager.contacts()) n += c.alive && c.gjkWarmStart.count > 0;
    return n;
}

TEST(GjkWarmStartSnapshot, HullPairsResumeBitForBitWithTheirStarts) {
    World original = rockHeap();
    for (int i = 0; i < 60; ++i) original.step(kDt);
    const std::size_t starts = warmStarts(original);
    ASSERT_GT(starts, 10u) << "the rocks must be in the heap, with warm starts";
    const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(original);
    EXPECT_EQ(bytes[8], kSnapshotVersion);
    World resumed = loadSnapshotFromMemory(bytes);
    EXPECT_EQ(warmStarts(resumed), starts);
    // A version-11 file has no starts: its pairs' GJK starts cold, ends a
    // few ulps elsewhere, and the heap goes its own way.
    World fromEleven = loadSnapshotFromMemory(detail::saveSnapshotAsVersion(original, 11));
    EXPECT_EQ(warmStarts(fromEleven), 0u);
    bool elevenDiverged = false;
    for (int i = 0; i < 90; ++i) {
        original.step(kDt);
        resumed.step(kDt);
        fromEleven.step(kDt);
        ASSERT_EQ(test::stateHash(resumed), test::stateHash(original)) << "diverged at step " << i + 1;
        elevenDiverged = elevenDiverged || test::stateHash(fromEleven) != test::stateHash(original);
    }
    EXPECT_TRUE(elevenDiverged) << "the warm start must matter in this scene";
}

// The start is each contact's own, written by whichever worker collides the
// pair: the same bits on one thread as on three.
TEST(GjkWarmStartSnapshot, TheWarmRunIsTheSameOnAnyThreadCount) {
    World one = rockHeap();
    World three = rockHeap();
    one.setThreadCount(1);
    three.setThreadCount(3);
    for (int i = 0; i < 120; ++i) {
        one.step(kDt);
        three.step(kDt);
        ASSERT_EQ(test::stateHash(three), test::stateHash(one)) << "diverged at step " << i + 1;
    }
    EXPECT_GT(warmStarts(one), 10u);
}

TEST(GjkWarmStartSnapshot, AStartOfMoreThanThreeVerticesIsRefused) {
    World world = rockHeap();
    for (int i = 0; i < 60; ++i) world.step(kDt);
    std::vector<std::uint8_t> bytes = saveSnapshotToMemory(world);
    ASSERT_NO_THROW((void)loadSnapshotFromMemory(bytes));
    const detail::Contact* held = nullptr;
    for (const detail::Contact& c : detail::implOf(world).contactManager.contacts()) {
        if (c.alive && c.gjkWarmStart.count == 3) held = &c;
    }
    ASSERT_NE(held, nullptr);
    // The start as the format writes it (little-endian): the count, then
    // each vertex's index on A and on B.
    std::vector<std::uint8_t> record(28);
    const detail::GjkWarmStart& s = held->gjkWarmStart;
    std::memcpy(record.data(), &s.count, 4);
    for (std::size_t i = 0; i < 3; ++i) {
        std::memcpy(record.data() + 4 + 8 * i, &s.indexA[i], 4);
        std::memcpy(record.data() + 8 + 8 * i, &s.indexB[i], 4);
    }
    const auto at = std::search(bytes.begin() + 32, bytes.end(), record.begin(), record.end());
    ASSERT_NE(at, bytes.end());
    *at = 4;  // four vertices: one more than a start holds
    std::uint64_t h = 14695981039346656037ull;  // the format's checksum (FNV-1a of the payload)
    for (std::size_t i = 32; i < bytes.size(); ++i) {
        h ^= bytes[i];
        h *= 1099511628211ull;
    }
    for (std::size_t i = 0; i < 8; ++i) bytes[24 + i] = static_cast<std::uint8_t>(h >> (8 * i));
    try {
        (void)loadSnapshotFromMemory(bytes);
        FAIL() << "a warm start of four vertices loaded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("GJK warm start"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace fulcrum
