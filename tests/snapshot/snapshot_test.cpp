// Snapshot format: round trips, handles, the shapes, and clear errors for
// foreign, corrupt and truncated data. (Bit-exact resumption of the physics
// is proved in tests/determinism.)
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "determinism/state_hash.hpp"
#include "fulcrum/scene.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"
#include "world/world_access.hpp"

namespace fulcrum {
namespace {

using test::stateHash;

World steppedMixed(int steps) {
    const Scene scene = parseScene(test::kMixedScene, "mixed");
    World w = buildWorld(scene);
    for (int i = 0; i < steps; ++i) w.step(scene.dt);
    return w;
}

std::string errorOf(const std::vector<std::uint8_t>& bytes) {
    try {
        (void)loadSnapshotFromMemory(bytes, nullptr, "snap.bin");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Snapshot, SaveLoadSaveGivesTheSameBytes) {
    // Everything read is written back equal: the strongest round-trip check of the format.
    const World w = steppedMixed(40);
    const auto first = saveSnapshotToMemory(w, "dt=0.0166667");
    std::string user;
    const World loaded = loadSnapshotFromMemory(first, &user);
    EXPECT_EQ(user, "dt=0.0166667");
    EXPECT_EQ(saveSnapshotToMemory(loaded, user), first);
    EXPECT_EQ(stateHash(loaded), stateHash(w));
    EXPECT_EQ(loaded.stepCount(), 40u);
    EXPECT_EQ(loaded.time(), w.time());
}

TEST(Snapshot, HandlesNamesAndSettingsSurvive) {
    World w = steppedMixed(10);
    w.setSolverIterations(3);
    // Free slots: destroy a body and a particle system, so the loaded world must
    // hand out the same new handles.
    w.destroyBody(w.findBody("s1"));
    const World loadedConst = loadSnapshotFromMemory(saveSnapshotToMemory(w));
    World loaded = loadSnapshotFromMemory(saveSnapshotToMemory(w));
    EXPECT_EQ(loaded.settings().solverIterations, 3);
    ASSERT_EQ(loaded.bodies(), w.bodies());
    for (const BodyId id : w.bodies()) {
        EXPECT_EQ(loaded.name(id), w.name(id));
        EXPECT_EQ(loaded.shape(id).type(), w.shape(id).type());
        EXPECT_EQ(loaded.mass(id), w.mass(id));
        EXPECT_EQ(loaded.previousTransform(id).p, w.previousTransform(id).p);
    }
    ASSERT_EQ(loaded.joints(), w.joints());
    for (const JointId id : w.joints()) EXPECT_EQ(loaded.name(id), w.name(id));
    ASSERT_EQ(loaded.particleSystems(), w.particleSystems());
    BodyDef def;
    def.name = "new";
    def.position = {10, 1, 10};
    EXPECT_EQ(loaded.createBody(def), w.createBody(def));
    EXPECT_TRUE(loadedConst.findBody("s1").isNull());
}

TEST(Snapshot, PendingForcesAndSharedShapes) {
    // A force applied before the snapshot acts in the next step of both worlds;
    // a hull shared by two bodies stays one geometry.
    World w;
    const Vec3 pts[] = {{-0.3f, 0, -0.2f}, {0.3f, 0, -0.2f}, {0, 0, 0.3f}, {0, 0.4f, 0}, {0.05f, 0.1f, 0.05f}};
    const Shape hull = Shape::convexHull(pts);
    BodyDef def;
    def.shape = hull;
    def.position = {0, 1, 0};
    const BodyId a = w.createBody(def);
    def.position = {2, 1, 0};
    w.createBody(def);
    w.applyForce(a, {5, 0, 0}, {0, 1.2f, 0});
    World loaded = loadSnapshotFromMemory(saveSnapshotToMemory(w));
    const auto bodies = loaded.bodies();
    EXPECT_EQ(&loaded.shape(bodies[0]).hull(), &loaded.shape(bodies[1]).hull());
    EXPECT_EQ(loaded.shape(bodies[0]).hull().faces.size(), hull.hull().faces.size());
    w.step(0.01f);
    loaded.step(0.01f);
    EXPECT_EQ(stateHash(loaded), stateHash(w));
    EXPECT_GT(loaded.linearVelocity(a).x, 0);  // the pending force acted: v = F dt / m > 0
}

TEST(Snapshot, FileRoundTrip) {
    const auto path = std::filesystem::temp_directory_path() / "fulcrum_snapshot_test.snap";
    const World w = steppedMixed(5);
    saveSnapshot(w, path, "hello");
    std::string user;
    const World loaded = loadSnapshot(path, &user);
    EXPECT_EQ(user, "hello");
    EXPECT_EQ(stateHash(loaded), stateHash(w));
    std::filesystem::remove(path);
    try {
        (void)loadSnapshot(path);
        FAIL() << "a missing file must throw";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
    }
}

TEST(Snapshot, UnknownVersionIsRefused) {
    auto bytes = saveSnapshotToMemory(steppedMixed(1));
    const std::string next = std::to_string(kSnapshotVersion + 1), last = std::to_string(kSnapshotVersion);
    bytes[8] = static_cast<std::uint8_t>(kSnapshotVersion + 1);
    EXPECT_EQ(errorOf(bytes), "snap.bin: unsupported snapshot version " + next + " (this build reads versions 2 to " + last + ")");
}

TEST(Snapshot, ForeignFileIsRefused) {
    const std::string text = "{\"world\": {}}";
    const std::vector<std::uint8_t> bytes(text.begin(), text.end());
    EXPECT_NE(errorOf(bytes).find("not a Fulcrum snapshot"), std::string::npos);
}

TEST(Snapshot, CorruptByteIsCaughtByTheChecksum) {
    const auto good = saveSnapshotToMemory(steppedMixed(20));
    for (std::size_t at : {std::size_t(40), good.size() / 2, good.size() - 1}) {
        auto bytes = good;
        bytes[at] ^= 0x10;
        EXPECT_NE(errorOf(bytes).find("checksum mismatch"), std::string::npos) << at;
    }
    auto longer = good;
    longer.push_back(0);
    EXPECT_NE(errorOf(longer).find("bytes after the end"), std::string::npos);
}

TEST(Snapshot, TruncationNamesTheByteAndThePart) {
    const auto good = saveSnapshotToMemory(steppedMixed(20));
    // In the header.
    EXPECT_EQ(errorOf({good.begin(), good.begin() + 20}), "snap.bin: truncated at byte 20 (header, 32 bytes)");
    // Every cut point gives "truncated at byte N (part)", N the offset of the
    // first item that is cut off, so N <= the file length.
    const std::string prefix = "snap.bin: truncated at byte ";
    for (std::size_t cut = 33; cut < good.size(); cut += good.size() / 97) {
        const std::string what = errorOf({good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut)});
        ASSERT_EQ(what.rfind(prefix, 0), 0u) << what;
        EXPECT_LE(std::stoull(what.substr(prefix.size())), cut) << what;
        EXPECT_NE(what.find(" ("), std::string::npos) << what;
    }
    // A cut inside the body records names the body.
    const std::string mid = errorOf({good.begin(), good.begin() + static_cast<std::ptrdiff_t>(good.size() / 8)});
    EXPECT_NE(mid.find("bodies["), std::string::npos) << mid;
    // The file ends with the vehicles' section (version 6): without vehicles,
    // the 8-byte counts of their slots, free slots and order. Cut 3 bytes off
    // and the last count is the one cut.
    EXPECT_EQ(errorOf({good.begin(), good.end() - 3}), prefix + std::to_string(good.size() - 8) + " (vehicles)");
}

TEST(Snapshot, InconsistentContentIsRefused) {
    // A structurally wrong file with a valid checksum (a buggy writer) is
    // rejected by the consistency checks instead of crashing a later step.
    World w = steppedMixed(3);
    const std::uint32_t slot = detail::implOf(w).denseToSlot[0];
    detail::implOf(w).denseToSlot[0] = 9999;  // a body pointing at a slot that does not exist
    const auto bytes = saveSnapshotToMemory(w);
    detail::implOf(w).denseToSlot[0] = slot;
    const std::string what = errorOf(bytes);
    EXPECT_NE(what.find("inconsistent snapshot"), std::string::npos) << what;
}

}  // namespace
}  // namespace fulcrum

// Found by fuzz/snapshot_fuzz.cpp (the file is its reproducer, checksum
// right): a body's centre of mass in its shape's frame was NaN, the load
// accepted it and the first step's broad phase got a NaN box. Every number
// the step reads without checking is now checked when loading.
namespace {

std::string loadErrorOf(const char* corpusFile) {
    const std::string file = std::string(FULCRUM_SOURCE_DIR) + "/fuzz/corpus/snapshot/" + corpusFile;
    std::ifstream in(file, std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() <= 32) return "missing " + file;
    try {
        (void)fulcrum::loadSnapshotFromMemory(bytes, nullptr, corpusFile);
    } catch (const fulcrum::Error& e) {
        return e.what();
    }
    return "loaded";
}

// The corpus files are float snapshots, so the double build refuses each by
// its precision before reading further (precision_snapshot_test.cpp): the
// loader's checks below are exercised by the float build.
std::string refusal(const char* corpusFile, const std::string& reason) {
    if constexpr (sizeof(fulcrum::Real) == sizeof(double)) {
        return std::string(corpusFile) + ": written with 32-bit reals, this build uses 64-bit reals";
    }
    return std::string(corpusFile) + ": " + reason;
}

}  // namespace

TEST(Snapshot, NonFiniteBodyStateIsRefusedWhenLoading) {
    EXPECT_EQ(loadErrorOf("nan_local_com.snap"),
              refusal("nan_local_com.snap", "inconsistent snapshot: bodies[2] mass, material or damping not finite"));
}

// Also found by fuzz/snapshot_fuzz.cpp: a cloth with a non-finite particle
// loaded, and its first step's self-collision grid indexed past its table
// (a heap overflow under AddressSanitizer).
TEST(Snapshot, NonFiniteParticleStateIsRefusedWhenLoading) {
    EXPECT_EQ(loadErrorOf("bad_particle.snap"),
              refusal("bad_particle.snap",
                      "inconsistent snapshot: particle system 'c1' positions, masses, radii or material not finite"));
    // A particle radius of 0 made the grid's cell size 0, and the search for
    // a cell size that fits the table never ended (a hang, not a crash).
    EXPECT_EQ(loadErrorOf("zero_particle_radius.snap"),
              refusal("zero_particle_radius.snap",
                      "inconsistent snapshot: particle system 'c1' positions, masses, radii or material not finite"));
}

// The particle world's own sub-steps and sweeps, which no World changes, came
// from the file unchecked: 4e7 x 6e6 ran for ever (found by fuzz/snapshot_fuzz.cpp).
TEST(Snapshot, ParticleSettingsOutsideTheLimitsAreRefusedWhenLoading) {
    EXPECT_EQ(loadErrorOf("huge_particle_substeps.snap"),
              refusal("huge_particle_substeps.snap",
                      "inconsistent snapshot: particle settings: substeps 39657488 and iterations "
                      "6316032 must be at most 1000 and 1000"));
}

// The contact free list came from the file unchecked: a head past the end
// made the first new contact write outside the table (a SEGV; found by
// fuzz/snapshot_fuzz.cpp).
TEST(Snapshot, ABadContactFreeListIsRefusedWhenLoading) {
    EXPECT_EQ(loadErrorOf("bad_free_contact.snap"), refusal("bad_free_contact.snap", "inconsistent snapshot: free contact list"));
}

// The particle systems' checks walked the world's list of live systems, the
// particle step every live slot: a list naming one system twice (and so
// missing another) left that one unchecked, and its constraint indices ran
// past its particles in the first step (a SEGV; found by a 10^6-input run of
// fuzz/snapshot_fuzz.cpp). The list must name every live slot once.
TEST(Snapshot, ALiveParticleSystemListedTwiceIsRefusedWhenLoading) {
    EXPECT_EQ(loadErrorOf("particle_system_listed_twice.snap"),
              refusal("particle_system_listed_twice.snap", "inconsistent snapshot: live particle system listed twice"));
}

// Found by fuzz/snapshot_fuzz.cpp: a snapshot that loads, every number
// finite, whose first step's self-collision grid computed a negative cell
// coordinate and converted it to an unsigned index (undefined behaviour,
// UBSan's report; the sanitizer pass of the test command runs this). The
// file is the reproducer (its checksum corrected here, as the target does).
TEST(Snapshot, SelfCollisionGridOfALoadedClothStaysInItsTable) {
    const std::filesystem::path file =
        std::filesystem::path(FULCRUM_SOURCE_DIR) / "fuzz" / "corpus" / "snapshot" / "self_collision_cell_index.snap";
    std::ifstream in(file, std::ios::binary);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 32u) << "missing " << file.string();
    std::uint64_t h = 14695981039346656037ull;  // the format's checksum (FNV-1a of the payload)
    for (std::size_t i = 32; i < bytes.size(); ++i) {
        h ^= bytes[i];
        h *= 1099511628211ull;
    }
    for (std::size_t i = 0; i < 8; ++i) bytes[24 + i] = static_cast<std::uint8_t>(h >> (8 * i));
    try {
        fulcrum::World world = fulcrum::loadSnapshotFromMemory(bytes, nullptr, "self_collision_cell_index.snap");
        world.setThreadCount(1);
        for (int i = 0; i < 3; ++i) world.step(fulcrum::Real(1) / fulcrum::Real(60));
        SUCCEED() << "loaded and stepped";
    } catch (const fulcrum::Error& e) {
        SUCCEED() << "refused: " << e.what();
    }
}

// Found by a 10^6-input run of fuzz/snapshot_fuzz.cpp: a snapshot whose
// compound body is 1e13 m across over a mesh loaded, and its first step hung
// in the mesh contacts' grouping (FuzzFindings.MeshContactGroupingEndsWhenANormalIsNotUnit
// has the cause and its fix). Since the shape size limit (kMaxShapeCoordinate,
// 10^12 m) the file is refused when loading, naming the shape.
TEST(Snapshot, AHugeCompoundOverAMeshIsRefusedBySizeLimit) {
    EXPECT_EQ(loadErrorOf("mesh_contact_normal_not_unit.snap"),
              refusal("mesh_contact_normal_not_unit.snap",
                      "a shape's size is not finite or beyond the limit of 1e12 m at byte 1196 (shapes[7])"));
}

// Found by fuzz/snapshot_fuzz.cpp: a compound child at -3.4e38 m (finite)
// with a zero orientation loaded, and once its body turned, the child's
// bounds overflowed to infinity inside the step (an assertion in the broad
// phase). Compound children are now held to Shape::compound's rules and
// every shape to the size limit (kMaxShapeCoordinate; tests/shapes/shape_limits_test.cpp).
TEST(Snapshot, ACompoundChildFarAwayIsRefusedWhenLoading) {
    EXPECT_EQ(loadErrorOf("compound_child_far_away.snap"),
              refusal("compound_child_far_away.snap",
                      "a compound child's position is not finite or beyond the limit of 1e12 m, or its "
                      "orientation is not a unit quaternion at byte 1126 (shapes[7])"));
}
