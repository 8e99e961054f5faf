// `fulcrum run --snapshot-at N --snapshot FILE` and `fulcrum run --resume FILE`
// through the command's library entry point: the resumed run's --json report
// equals the uninterrupted run's (wall time aside), bit for bit in every number.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "fulcrum/scene.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"
#include "io/run.hpp"

namespace fulcrum {
namespace {

struct Outcome {
    int status = 0;
    std::string out, err;
};

Outcome runCli(const std::optional<std::string>& scene, detail::RunOverrides o, detail::RunOutputs outputs) {
    std::ostringstream out, err;
    const int status = detail::runCommand(scene, o, outputs, out, err);
    return {status, out.str(), err.str()};
}

nlohmann::json report(const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text);
    j.erase("wall_seconds");
    return j;
}

TEST(CliResume, ResumedReportEqualsTheUninterruptedRun) {
    const std::string scene = std::string(FULCRUM_SOURCE_DIR) + "/scenes/rope_and_cloth.json";
    const auto snap = std::filesystem::temp_directory_path() / "fulcrum_cli_resume.snap";
    detail::RunOverrides o;
    o.steps = 90;
    detail::RunOutputs json;
    json.json = true;
    const Outcome full = runCli(scene, o, json);
    ASSERT_EQ(full.status, 0) << full.err;

    detail::RunOutputs withSnap = json;
    withSnap.snapshotAt = 40;
    withSnap.snapshotPath = snap.string();
    const Outcome first = runCli(scene, o, withSnap);
    ASSERT_EQ(first.status, 0) << first.err;
    EXPECT_EQ(report(first.out), report(full.out));  // saving changes nothing

    detail::RunOverrides resume;
    resume.resumePath = snap.string();
    const Outcome resumed = runCli(std::nullopt, resume, json);  // the rest of the 90 steps
    ASSERT_EQ(resumed.status, 0) << resumed.err;
    EXPECT_EQ(report(resumed.out), report(full.out));
    EXPECT_EQ(report(resumed.out)["steps"], 90);

    resume.steps = 10;  // --steps counts further steps
    const Outcome ten = runCli(std::nullopt, resume, json);
    EXPECT_EQ(report(ten.out)["steps"], 50);
    std::filesystem::remove(snap);
}

TEST(CliResume, BadSnapshotsAndOptionsExitWithStatus2) {
    const auto bad = std::filesystem::temp_directory_path() / "fulcrum_cli_bad.snap";
    std::ofstream(bad, std::ios::binary) << "FULCSNAP\x07";
    detail::RunOverrides resume;
    resume.resumePath = bad.string();
    const Outcome truncated = runCli(std::nullopt, resume, {});
    EXPECT_EQ(truncated.status, 2);
    EXPECT_EQ(truncated.err, "fulcrum: " + bad.string() + ": truncated at byte 9 (header, 32 bytes)\n");
    std::filesystem::remove(bad);

    detail::RunOutputs noFile;
    noFile.snapshotAt = 3;
    const Outcome missing = runCli(std::nullopt, {}, noFile);
    EXPECT_EQ(missing.status, 2);
    EXPECT_NE(missing.err.find("--snapshot-at: needs --snapshot FILE"), std::string::npos) << missing.err;
}

// Found by fuzzing a snapshot: a body name is bytes (the C++ API and the
// snapshot take any), and a name that is not UTF-8 made the --json report
// fail with the JSON library's "invalid UTF-8 byte" as an internal error.
// The report is written instead, the bad bytes as U+FFFD, the rest intact.
TEST(CliResume, ANameThatIsNotUtf8IsReportedWithReplacementCharacters) {
    World world;
    BodyDef def;
    def.name = "crate\xff\xfe";
    def.shape = Shape::box({Real(0.5), Real(0.5), Real(0.5)});
    def.position = {0, 2, 0};
    (void)world.createBody(def);
    const auto snap = std::filesystem::temp_directory_path() / "fulcrum_cli_not_utf8.snap";
    saveSnapshot(world, snap, R"({"fulcrum_run": 1, "dt": 0.01, "steps": 5, "source": "bytes\u00e9"})");
    detail::RunOverrides resume;
    resume.resumePath = snap.string();
    detail::RunOutputs json;
    json.json = true;
    const Outcome resumed = runCli(std::nullopt, resume, json);
    std::filesystem::remove(snap);
    ASSERT_EQ(resumed.status, 0) << resumed.err;
    const nlohmann::json r = report(resumed.out);
    EXPECT_EQ(r["steps"], 5);
    EXPECT_NE(resumed.out.find("crate\xEF\xBF\xBD\xEF\xBF\xBD"), std::string::npos) << resumed.out;
    // The body still fell under gravity for 5 steps of 0.01 s (not a stub report).
    EXPECT_LT(r["bodies"][0]["position"][1].get<double>(), 2.0);
}

// --push-out-grown-overlaps with --resume changes the run from the snapshot
// on: a struck row (no gravity, a 10 kg box at 20 m/s into five unit boxes,
// where the push-out acts in the first steps) saved after step 1 without the
// push-out and resumed with it ends, number for number, as the C++ world
// stepped once, switched on by World::setPushOutGrownOverlaps and stepped on;
// resumed without the option it ends as the uninterrupted run without it.
TEST(CliResume, PushOutOptionChangesTheResumedRunFromThere) {
    std::string bodies = R"({"shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 10, "friction": 0,
                             "position": [-1.5, 0, 0], "linear_velocity": [20, 0, 0]})";
    for (int i = 0; i < 5; ++i) {
        bodies += R"(, {"shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 1, "friction": 0, "position": [)" +
                  std::to_string(i) + ", 0, 0]}";
    }
    const auto dir = std::filesystem::temp_directory_path();
    const auto scenePath = dir / "fulcrum_cli_resume_row.json", snap = dir / "fulcrum_cli_resume_row.snap";
    std::ofstream(scenePath) << R"({"world": {"gravity": [0, 0, 0], "dt": 0.0166667, "steps": 30}, "bodies": [)" + bodies + "]}";
    detail::RunOutputs json;
    json.json = true;
    detail::RunOutputs withSnap = json;
    withSnap.snapshotAt = 1;
    withSnap.snapshotPath = snap.string();
    const Outcome off = runCli(scenePath.string(), {}, withSnap);
    ASSERT_EQ(off.status, 0) << off.err;

    detail::RunOverrides resume;
    resume.resumePath = snap.string();
    const Outcome plain = runCli(std::nullopt, resume, json);
    ASSERT_EQ(plain.status, 0) << plain.err;
    EXPECT_EQ(report(plain.out), report(off.out));
    resume.pushOutGrownOverlaps = true;
    const Outcome on = runCli(std::nullopt, resume, json);
    ASSERT_EQ(on.status, 0) << on.err;
    const nlohmann::json ends = report(on.out)["bodies"];
    EXPECT_NE(ends, report(off.out)["bodies"]) << "the push-out never acted: the test does not test the option";

    const Scene scene = loadScene(scenePath);
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    world.step(scene.dt);
    world.setPushOutGrownOverlaps(true);
    for (int i = 1; i < 30; ++i) world.step(scene.dt);
    ASSERT_EQ(ends.size(), handles.bodies.size());
    for (std::size_t i = 0; i < handles.bodies.size(); ++i) {
        const Vec3 p = world.position(handles.bodies[i]);
        const nlohmann::json& q = ends[i]["position"];
        // The report's numbers are the shortest decimals of the engine's: read back, the same bits.
        EXPECT_TRUE(Real(q[0].get<double>()) == p.x && Real(q[1].get<double>()) == p.y && Real(q[2].get<double>()) == p.z)
            << "body " << i << ": " << q << " against (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
    std::filesystem::remove(scenePath);
    std::filesystem::remove(snap);
}

}  // namespace
}  // namespace fulcrum
