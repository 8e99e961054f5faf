// Snapshot format version 11: each contact's triangle axis cache (a box or
// hull against a mesh; collision/manifold.hpp, TriangleAxisCache). The cache
// decides which axis the next step's triangle tests take, so a world saved
// with it resumes bit for bit, and one whose cache is dropped (a version-10
// file) goes its own way.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
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

// Hex prisms and boxes (single and a two-piece compound) tumbling onto a
// wave mesh of 0.5 m cells.
World logsOnWaves() {
    World world(WorldDef{});
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    constexpr int kCells = 24;
    for (int i = 0; i <= kCells; ++i) {
        for (int j = 0; j <= kCells; ++j) {
            const Real x = Real(0.5) * Real(i) - 6, z = Real(0.5) * Real(j) - 6;
            vertices.push_back({x, Real(0.3) * std::sin(Real(0.8) * x) * std::cos(Real(0.6) * z), z});
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
    for (int i = 0; i < 6; ++i) {
        BodyDef d;
        d.shape = i % 3 == 2 ? Shape::box({Real(0.4), Real(0.25), Real(0.5)}) : log;
        d.position = {Real(1.7) * Real(i) - 4, Real(1.2) + Real(0.3) * Real(i % 2), Real(0.9) * Real(i % 3) - 1};
        d.orientation = Quat::fromAxisAngle(normalize(Vec3{Real(0.3), 1, Real(0.2) * Real(i)}), Real(0.4) * Real(i));
        d.linearVelocity = {Real(0.5), 0, Real(-0.3)};
        d.angularVelocity = {Real(0.8), Real(0.2), Real(-1.1)};
        world.createBody(d);
    }
    return world;
}

std::size_t cachedEntries(const World& world) {
    std::size_t n = 0;
    for (const detail::Contact& c : detail::implOf(world).contactManager.contacts()) n += c.alive ? c.triangleAxes.size() : 0;
    return n;
}

TEST(TriangleAxisSnapshot, MeshContactsResumeBitForBitWithTheirCache) {
    World original = logsOnWaves();
    for (int i = 0; i < 45; ++i) original.step(kDt);
    const std::size_t entries = cachedEntries(original);
    ASSERT_GT(entries, 10u) << "the pieces must be on the mesh, with cached axes";
    const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(original);
    EXPECT_EQ(bytes[8], kSnapshotVersion);
    World resumed = loadSnapshotFromMemory(bytes);
    EXPECT_EQ(cachedEntries(resumed), entries);
    // A version-10 file has no cache: its pairs run the full test and keep
    // other axes than the cache would, so the run goes its own way.
    World fromTen = loadSnapshotFromMemory(detail::saveSnapshotAsVersion(original, 10));
    EXPECT_EQ(cachedEntries(fromTen), 0u);
    bool tenDiverged = false;
    for (int i = 0; i < 90; ++i) {
        original.step(kDt);
        resumed.step(kDt);
        fromTen.step(kDt);
        ASSERT_EQ(test::stateHash(resumed), test::stateHash(original)) << "diverged at step " << i + 1;
        tenDiverged = tenDiverged || test::stateHash(fromTen) != test::stateHash(original);
    }
    EXPECT_TRUE(tenDiverged) << "the cache must matter in this scene";
}

// The cache is each contact's own, written by whichever worker collides the
// pair: the same bits on one thread as on three.
TEST(TriangleAxisSnapshot, TheCachedRunIsTheSameOnAnyThreadCount) {
    World one = logsOnWaves();
    World three = logsOnWaves();
    one.setThreadCount(1);
    three.setThreadCount(3);
    for (int i = 0; i < 120; ++i) {
        one.step(kDt);
        three.step(kDt);
        ASSERT_EQ(test::stateHash(three), test::stateHash(one)) << "diverged at step " << i + 1;
    }
    EXPECT_GT(cachedEntries(one), 10u);
}

TEST(TriangleAxisSnapshot, AnUnsortedCacheIsRefused) {
    World world = logsOnWaves();
    for (int i = 0; i < 45; ++i) world.step(kDt);
    std::vector<std::uint8_t> bytes = saveSnapshotToMemory(world);
    ASSERT_NO_THROW((void)loadSnapshotFromMemory(bytes));
    // Two entries of a contact, swapped in the file (the checksum corrected,
    // as a buggy writer would leave it): the search for a triangle's entry
    // needs them in order, so the file is refused.
    const detail::Contact* held = nullptr;
    for (const detail::Contact& c : detail::implOf(world).contactManager.contacts()) {
        if (c.alive && c.triangleAxes.size() >= 2) held = &c;
    }
    ASSERT_NE(held, nullptr);
    constexpr std::size_t kEntryBytes = 12 + sizeof(Real);  // little-endian fields, as the format writes them
    const auto bytesOf = [](const detail::TriangleAxisEntry& e) {
        std::vector<std::uint8_t> b(kEntryBytes);
        std::memcpy(b.data(), &e.piece, 4);
        std::memcpy(b.data() + 4, &e.triangle, 4);
        std::memcpy(b.data() + 8, &e.axis, 4);
        std::memcpy(b.data() + 12, &e.separation, sizeof(Real));
        return b;
    };
    const std::vector<std::uint8_t> first = bytesOf(held->triangleAxes[0]), second = bytesOf(held->triangleAxes[1]);
    std::vector<std::uint8_t> pair = first;
    pair.insert(pair.end(), second.begin(), second.end());
    const auto at = std::search(bytes.begin(), bytes.end(), pair.begin(), pair.end());
    ASSERT_NE(at, bytes.end());
    std::copy(second.begin(), second.end(), at);
    std::copy(first.begin(), first.end(), at + static_cast<std::ptrdiff_t>(kEntryBytes));
    std::uint64_t h = 14695981039346656037ull;  // the format's checksum (FNV-1a of the payload)
    for (std::size_t i = 32; i < bytes.size(); ++i) {
        h ^= bytes[i];
        h *= 1099511628211ull;
    }
    for (std::size_t i = 0; i < 8; ++i) bytes[24 + i] = static_cast<std::uint8_t>(h >> (8 * i));
    try {
        (void)loadSnapshotFromMemory(bytes);
        FAIL() << "an unsorted cache loaded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("triangle axis cache is not sorted"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace fulcrum
