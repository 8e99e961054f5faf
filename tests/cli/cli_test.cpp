// The `fulcrum` binary, run as a user runs it: exit codes, one-line errors on
// stderr, the --json report, --csv rows, --plot SVG, and no progress bar in
// pipes. Step counts are small so the whole file runs in well under a second.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;

struct Result {
    int status = -1;
    std::string out, err;
};

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

fs::path tempDir() {
    const fs::path dir = fs::temp_directory_path() / ("fulcrum_cli_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

fs::path writeTemp(const std::string& name, const std::string& text) {
    const fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
}

// Runs `fulcrum ARGS` with stdout and stderr redirected to files (pipes, not a terminal).
Result fulcrum(const std::string& args) {
    const fs::path out = tempDir() / "stdout.txt", err = tempDir() / "stderr.txt";
    const std::string cmd = std::string("cd '") + FULCRUM_SOURCE_DIR + "' && '" + FULCRUM_CLI_PATH + "' " + args + " >'" +
                            out.string() + "' 2>'" + err.string() + "' </dev/null";
    const int raw = std::system(cmd.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = readFile(out);
    r.err = readFile(err);
    return r;
}

std::size_t lineCount(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

// A bad-input run: status 2, exactly one line on stderr containing every `part`.
void expectBadInput(const std::string& args, std::initializer_list<std::string> parts) {
    SCOPED_TRACE(args);
    const Result r = fulcrum(args);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(lineCount(r.err), 1u) << r.err;
    for (const std::string& part : parts) EXPECT_NE(r.err.find(part), std::string::npos) << "stderr: " << r.err << " lacks: " << part;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(Cli, DemoRunsWithoutArgumentsAndNoProgressBarInPipes) {
    const Result r = fulcrum("run");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("projectile"), std::string::npos);
    EXPECT_NE(r.out.find("demo checks"), std::string::npos);
    EXPECT_TRUE(r.err.empty()) << "stderr is a pipe: no progress bar, got: " << r.err;
    EXPECT_EQ(r.out.find('\r'), std::string::npos);
}

TEST(Cli, HelpAndVersion) {
    const Result help = fulcrum("--help");
    EXPECT_EQ(help.status, 0);
    EXPECT_NE(help.out.find("run"), std::string::npos);
    const Result runHelp = fulcrum("run --help");
    EXPECT_EQ(runHelp.status, 0);
    for (const char* opt : {"--steps", "--dt", "--substeps", "--integrator", "--threads", "--json", "--csv", "--record", "--plot"}) {
        EXPECT_NE(runHelp.out.find(opt), std::string::npos) << opt;
    }
    const Result version = fulcrum("--version");
    EXPECT_EQ(version.status, 0);
    EXPECT_EQ(version.out.rfind("fulcrum ", 0), 0u) << version.out;
}

TEST(Cli, JsonReportHasEveryContractKeyAndTheProjectileFollowsTheAnalyticPath) {
    const Result r = fulcrum("run scenes/projectile.json --json");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    for (const char* key : {"steps", "time", "wall_seconds", "bodies", "energy", "momentum", "contacts", "joints"}) {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    for (const char* key : {"kinetic", "potential", "total"}) EXPECT_TRUE(j["energy"].contains(key)) << key;
    for (const char* key : {"linear", "angular"}) EXPECT_TRUE(j["momentum"].contains(key)) << key;
    ASSERT_EQ(j["bodies"].size(), 1u);
    const auto& ball = j["bodies"][0];
    for (const char* key : {"name", "position", "orientation", "linear_velocity", "angular_velocity", "sleeping"}) {
        EXPECT_TRUE(ball.contains(key)) << key;
    }
    EXPECT_EQ(ball["name"], "ball");
    EXPECT_EQ(j["steps"], 120);

    // x(t) = x0 + v0 t + g t^2 / 2 with x0 = 0, v0 = (5, 10, 0), g = -9.81.
    // Semi-implicit Euler with step h is off by exactly g h t / 2 (it uses the
    // velocity at the end of each step); h <= dt, so the tolerance
    // |g| dt t / 2 = 0.164 m holds for any sub-step count, plus 1e-3 m for float
    // rounding. A wrong sign of g or a missing v0 term misses it by metres.
    const double t = j["time"].get<double>();
    EXPECT_NEAR(t, 2.0, 1e-4);
    const double dt = 0.0166667, tol = 9.81 * dt * t / 2 + 1e-3;
    EXPECT_NEAR(ball["position"][0].get<double>(), 5 * t, 1e-3);
    EXPECT_NEAR(ball["position"][1].get<double>(), 10 * t - 0.5 * 9.81 * t * t, tol);
    EXPECT_NEAR(ball["position"][2].get<double>(), 0, 1e-6);
    EXPECT_NEAR(ball["linear_velocity"][1].get<double>(), 10 - 9.81 * t, 1e-3);
}

// --profile: the phases of the step (World::lastStepProfile) averaged over the
// run. They are laps of one clock, so they add up to the mean step time (to
// double rounding); a stack of 8 boxes on the ground has 8 contact interfaces
// (7 box-box and 1 on the ground), each one manifold. Without --profile the
// report has no "profile" key (the JSON contract is unchanged).
TEST(Cli, ProfileReportsThePhasesOfTheStep) {
    const Result r = fulcrum("run scenes/box_stack.json --steps 30 --json --profile");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("profile"));
    const auto& p = j["profile"];
    EXPECT_EQ(p["steps"], 30);
    double sum = 0;
    for (const char* phase : {"collide", "prepare", "solve", "store", "continuous", "particles", "sleep", "finish"}) {
        ASSERT_TRUE(p.contains(phase)) << phase;
        EXPECT_GE(p[phase].get<double>(), 0.0) << phase;
        sum += p[phase].get<double>();
    }
    EXPECT_GT(p["ms_per_step"].get<double>(), 0.0);
    EXPECT_NEAR(sum, p["ms_per_step"].get<double>(), 1e-9 * p["ms_per_step"].get<double>());
    EXPECT_EQ(p["max_awake_bodies"], 8);
    EXPECT_EQ(p["max_contact_constraints"], 8);
    EXPECT_EQ(p["max_joint_constraints"], 0);

    const Result table = fulcrum("run scenes/box_stack.json --steps 30 --profile");
    ASSERT_EQ(table.status, 0) << table.err;
    EXPECT_NE(table.out.find("profile: 30 steps"), std::string::npos) << table.out;
    EXPECT_NE(table.out.find("  solve "), std::string::npos) << table.out;

    const Result plain = fulcrum("run scenes/box_stack.json --steps 3 --json");
    ASSERT_EQ(plain.status, 0) << plain.err;
    EXPECT_FALSE(nlohmann::json::parse(plain.out).contains("profile"));
}

TEST(Cli, OptionsOverrideTheScene) {
    const Result r = fulcrum("run scenes/projectile.json --json --steps 7 --dt 0.01 --substeps 2 --integrator verlet --threads 1");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["steps"], 7);
    EXPECT_NEAR(j["time"].get<double>(), 0.07, 1e-6);
}

TEST(Cli, CsvHasOneRowPerStepAndDynamicBody) {
    // box_stack: 8 dynamic boxes and a static ground; 5 steps -> (5 + 1) * 8 rows + header.
    const fs::path csv = tempDir() / "out.csv";
    const Result r = fulcrum("run scenes/box_stack.json --steps 5 --csv '" + csv.string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string text = readFile(csv);
    EXPECT_EQ(lineCount(text), 6u * 8u + 1u);
    EXPECT_EQ(text.rfind("step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n", 0), 0u);
    EXPECT_NE(text.find("\n0,0,box0,"), std::string::npos);
    EXPECT_NE(text.find("\n5,"), std::string::npos);
    EXPECT_EQ(text.find(",ground,"), std::string::npos) << "static bodies have no rows";
}

TEST(Cli, PlotWritesAnSvg) {
    const fs::path svg = tempDir() / "energy.svg";
    const Result r = fulcrum("run scenes/spring_mass.json --steps 50 --plot '" + svg.string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string text = readFile(svg);
    EXPECT_EQ(text.rfind("<svg", 0), 0u);
    EXPECT_NE(text.find("<polyline"), std::string::npos);
    EXPECT_NE(text.find("total"), std::string::npos);
}

TEST(Cli, RecordWritesGlbAndHtml) {
    // 20 steps -> 21 frames of one moving body: the GLB starts with the glTF
    // magic and version 2; the page embeds its scripts (tests/recording's
    // browser test checks it makes no network request at all).
    const fs::path glb = tempDir() / "run.glb";
    const fs::path html = tempDir() / "run.html";
    ASSERT_EQ(fulcrum("run scenes/projectile.json --steps 20 --record '" + glb.string() + "'").status, 0);
    ASSERT_EQ(fulcrum("run scenes/projectile.json --steps 20 --record '" + html.string() + "'").status, 0);
    const std::string bin = readFile(glb);
    ASSERT_GE(bin.size(), 20u);
    EXPECT_EQ(bin.substr(0, 4), "glTF");
    EXPECT_EQ(static_cast<unsigned char>(bin[4]), 2u);
    const std::string page = readFile(html);
    EXPECT_NE(page.find("<html"), std::string::npos);
    EXPECT_EQ(page.find("<script src"), std::string::npos) << "the page must embed its scripts, not load them";
}

TEST(Cli, BadInputExitsWith2AndOneLine) {
    expectBadInput("run scenes/does_not_exist.json", {"scenes/does_not_exist.json", "cannot open"});
    const fs::path bad = writeTemp("malformed.json", "{\n  \"bodies\": [,]\n}\n");
    expectBadInput("run '" + bad.string() + "'", {bad.string() + ":2:", "malformed JSON"});
    const fs::path typo = writeTemp("typo.json", "{\"bodies\": [\n  {\"shap\": {\"type\": \"sphere\", \"radius\": 1}}]}");
    expectBadInput("run '" + typo.string() + "'", {typo.string() + ":2: bodies[0].shap: unknown key", "shape"});
    const fs::path mass = writeTemp("mass.json", "{\"bodies\": [{\"shape\": {\"type\": \"sphere\", \"radius\": 1}, \"mass\": -1}]}");
    expectBadInput("run '" + mass.string() + "'", {"bodies[0].mass", "must be positive"});
    expectBadInput("run scenes/projectile.json --dt -1", {"--dt", "-1"});
    expectBadInput("run scenes/projectile.json --dt=0", {"--dt"});
    expectBadInput("run scenes/projectile.json --steps -3", {"--steps"});
    expectBadInput("run scenes/projectile.json --substeps 0", {"--substeps"});
    expectBadInput("run scenes/projectile.json --integrator foo", {"--integrator", "foo", "semi_implicit_euler"});
    expectBadInput("run scenes/projectile.json --steps many", {"--steps"});
    expectBadInput("run scenes/projectile.json --bogus", {"--bogus"});
    expectBadInput("run scenes/projectile.json --record out.txt", {"--record", "out.txt", ".glb or .html"});
}

TEST(Cli, NanStopsWith3AndNamesTheBody) {
    // Explicit Euler on a stiff spring (omega = 1e5 rad/s, h = 4 ms) grows the
    // amplitude by sqrt(1 + (omega h)^2) ~ 400 per step: past float range in a
    // few dozen steps, then NaN.
    const fs::path blowup = writeTemp("blowup.json", R"({"world": {"integrator": "explicit_euler", "dt": 0.004, "steps": 500, "substeps": 1},
      "bodies": [{"name": "rocket", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1, "position": [0, -1.5, 0]}],
      "springs": [{"body_b": "rocket", "anchor_a": [0, 0, 0], "anchor_b": [0, -1.5, 0], "rest_length": 1, "stiffness": 1e10}]})");
    const Result r = fulcrum("run '" + blowup.string() + "' --json");
    EXPECT_EQ(r.status, 3) << r.err;
    EXPECT_EQ(lineCount(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("rocket"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("step"), std::string::npos) << r.err;
}

// Issue 27: an alternating 1 kg / 10^6 kg stack is far beyond the mass ratio
// the solver holds (docs/solver.md, "Mass ratios"): the heavy boxes sink into
// the light ones. The run still succeeds (exit 0: the simulation did what its
// solver does, and a non-zero code would break scripts that batch-run scenes),
// but its summary says which bodies stay overlapped instead of looking like
// a stack at rest. A stack that holds prints no warning.
TEST(Cli, SummaryWarnsAboutBodiesLeftOverlapped) {
    std::string bodies = R"({"name": "ground", "type": "static", "shape": {"type": "box", "half_extents": [5, 0.5, 5]}, "position": [0, -0.5, 0]})";
    for (int i = 0; i < 5; ++i) {
        bodies += R"(, {"name": ")" + std::string(i % 2 ? "heavy" : "light") + std::to_string(i) +
                  R"(", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": )" + (i % 2 ? "1e6" : "1") +
                  R"(, "position": [0, )" + std::to_string(0.5 + i) + ", 0]}";
    }
    const fs::path sinking = writeTemp("mass_ratio.json", R"({"world": {"dt": 0.0166667, "steps": 120}, "bodies": [)" + bodies + "]}");
    const Result r = fulcrum("run '" + sinking.string() + "'");
    EXPECT_EQ(r.status, 0) << r.err;
    const std::size_t warning = r.out.find("warning:");
    ASSERT_NE(warning, std::string::npos) << r.out;
    const std::string tail = r.out.substr(warning);
    EXPECT_NE(tail.find("overlapped"), std::string::npos) << tail;
    // Each heavy box has sunk into a light one: both heavy boxes are named.
    EXPECT_NE(tail.find("heavy1"), std::string::npos) << tail;
    EXPECT_NE(tail.find("heavy3"), std::string::npos) << tail;
    EXPECT_NE(tail.find("light"), std::string::npos) << tail;

    const Result stack = fulcrum("run scenes/box_stack.json --steps 120");
    EXPECT_EQ(stack.status, 0) << stack.err;
    EXPECT_EQ(stack.out.find("warning"), std::string::npos) << stack.out;
}

}  // namespace
