// The `fulcrum` binary, run as a user runs it: exit codes, one-line errors on
// stderr, the --json report, --csv rows, --plot SVG, and no progress bar in
// pipes. Step counts are small so the whole file runs in well under a second.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "fulcrum/math/vec3.hpp"  // Real: the limits the CLI checks are its
#include "support/svg_points.hpp"

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

// Runs `fulcrum ARGS` with stdout and stderr redirected to files (pipes, not a
// terminal). A run that hangs is killed after two minutes (status 124), so a
// hang fails its test instead of stalling the suite.
Result fulcrum(const std::string& args) {
    const fs::path out = tempDir() / "stdout.txt", err = tempDir() / "stderr.txt";
    const std::string cmd = std::string("cd '") + FULCRUM_SOURCE_DIR + "' && timeout 120 '" + FULCRUM_CLI_PATH + "' " + args + " >'" +
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

// Issue 27: --json put every vector component on its own line (509 lines for
// 9 bodies). Vectors and quaternions are one line each, with the very numbers
// the parsed report holds (nlohmann prints a double's shortest exact text).
TEST(Cli, JsonPrintsEachVectorOnOneLine) {
    const Result r = fulcrum("run scenes/box_stack.json --steps 20 --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["bodies"].size(), 9u);
    const auto oneLine = [](const nlohmann::json& v) {
        std::string s = "[";
        for (std::size_t i = 0; i < v.size(); ++i) s += (i > 0 ? ", " : "") + v[i].dump();
        return s + "]";
    };
    for (const auto& body : j["bodies"]) {
        for (const char* key : {"position", "orientation", "linear_velocity", "angular_velocity"}) {
            std::string line = "\"";
            line.append(key).append("\": ").append(oneLine(body[key]));
            EXPECT_NE(r.out.find(line), std::string::npos) << "missing line: " << line;
        }
    }
    EXPECT_NE(r.out.find("\"linear\": " + oneLine(j["momentum"]["linear"])), std::string::npos) << r.out;
    for (const auto& c : j["contacts"]) {
        EXPECT_NE(r.out.find("\"normal\": " + oneLine(c["normal"])), std::string::npos);
        for (const auto& p : c["points"]) EXPECT_NE(r.out.find(oneLine(p)), std::string::npos);
        EXPECT_TRUE(c["normal_impulse"].is_number());  // the contract: terrain and contact forces
        EXPECT_EQ(c["force"].size(), 3u);
        EXPECT_NE(r.out.find("\"force\": " + oneLine(c["force"])), std::string::npos);
    }
    // No line is a bare number any more; the body block is about 8 lines a body.
    std::istringstream lines(r.out);
    std::size_t count = 0;
    for (std::string line; std::getline(lines, line); ++count) {
        const std::size_t at = line.find_first_not_of(' ');
        ASSERT_NE(at, std::string::npos);
        EXPECT_FALSE(line[at] == '-' || std::isdigit(static_cast<unsigned char>(line[at]))) << "a lone number: " << line;
    }
    EXPECT_LT(count, 9u * 10u + 40u + 10u * j["contacts"].size());  // a contact: 8 lines, 10 with its normal_impulse and force
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

TEST(Cli, SummaryAndJsonSayWhenThePairLimitHeldPairsBack) {
    // 40 spheres at one spot (780 pairs) under a limit of 100.
    std::string bodies;
    for (int i = 0; i < 40; ++i) {
        bodies += std::string(i ? ", " : "") + R"({"shape": {"type": "sphere", "radius": 0.5}, "mass": 1, "position": [0, 2, 0]})";
    }
    const fs::path scene = writeTemp("crowd.json", R"({"world": {"steps": 10, "max_contact_pairs": 100}, "bodies": [)" + bodies + "]}");
    const Result r = fulcrum("run '" + scene.string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("  warning (step 1): contact pair limit reached"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("the limit is 100 (WorldDef::maxContactPairs; scene files: world.max_contact_pairs)"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("contact pair limit 100 (world.max_contact_pairs) held new pairs back in "), std::string::npos) << r.out;
    const Result json = fulcrum("run '" + scene.string() + "' --json --profile");
    ASSERT_EQ(json.status, 0) << json.err;
    const nlohmann::json j = nlohmann::json::parse(json.out);
    ASSERT_TRUE(j.contains("warnings"));
    ASSERT_EQ(j["warnings"].size(), 1u);
    EXPECT_EQ(j["warnings"][0]["step"], 1);
    EXPECT_NE(j["warnings"][0]["message"].get<std::string>().find("contact pair limit reached"), std::string::npos);
    EXPECT_EQ(j["profile"]["contact_pair_limit"], 100);
    EXPECT_LE(j["profile"]["max_contact_pairs"].get<int>(), 100);
    EXPECT_GT(j["profile"]["steps_over_pair_limit"].get<int>(), 0);
    // A scene under its limit: no warnings key, no warning line.
    const Result calm = fulcrum("run scenes/box_stack.json --steps 3 --json");
    ASSERT_EQ(calm.status, 0) << calm.err;
    EXPECT_FALSE(nlohmann::json::parse(calm.out).contains("warnings"));
}

TEST(Cli, OptionsOverrideTheScene) {
    const Result r = fulcrum("run scenes/projectile.json --json --steps 7 --dt 0.01 --substeps 2 --integrator verlet --threads 1");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["steps"], 7);
    EXPECT_NEAR(j["time"].get<double>(), 0.07, 1e-6);
}

// --push-out-grown-overlaps overrides world.push_out_grown_overlaps
// (WorldDef::pushOutGrownOverlaps): on a row of unit boxes struck by a 10 kg
// box at 20 m/s (no gravity), where the push-out acts, the flag gives the
// bodies of the scene with the key on, number for number, and not those of
// the scene without it; =false on the scene with the key gives those of the
// scene without it. A value that is not a boolean is exit status 2, one line.
TEST(Cli, PushOutGrownOverlapsFlagOverridesTheScene) {
    const auto rowScene = [](const std::string& worldKeys) {
        std::string bodies = R"({"name": "striker", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 10,
                                 "friction": 0, "position": [-1.5, 0, 0], "linear_velocity": [20, 0, 0]})";
        for (int i = 0; i < 5; ++i) {
            bodies += R"(, {"name": "b)" + std::to_string(i) + R"(", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                        "mass": 1, "friction": 0, "position": [)" + std::to_string(i) + ", 0, 0]}";
        }
        return R"({"world": {"gravity": [0, 0, 0], "dt": 0.0166667, "steps": 30)" + worldKeys + R"(}, "bodies": [)" + bodies + "]}";
    };
    const fs::path plain = writeTemp("row_plain.json", rowScene(""));
    const fs::path keyed = writeTemp("row_push_out.json", rowScene(R"(, "push_out_grown_overlaps": true)"));
    const auto bodiesOf = [](const std::string& args) {
        const Result r = fulcrum("run " + args + " --json");
        EXPECT_EQ(r.status, 0) << args << ": " << r.err;
        return r.status == 0 ? nlohmann::json::parse(r.out)["bodies"] : nlohmann::json();
    };
    const nlohmann::json off = bodiesOf("'" + plain.string() + "'");
    const nlohmann::json on = bodiesOf("'" + keyed.string() + "'");
    ASSERT_EQ(on.size(), 6u);
    EXPECT_NE(on, off) << "the push-out never acted: the test does not test the flag";
    EXPECT_EQ(bodiesOf("'" + plain.string() + "' --push-out-grown-overlaps"), on);
    EXPECT_EQ(bodiesOf("'" + plain.string() + "' --push-out-grown-overlaps=true"), on);
    EXPECT_EQ(bodiesOf("'" + keyed.string() + "' --push-out-grown-overlaps=false"), off);
    expectBadInput("run '" + plain.string() + "' --push-out-grown-overlaps=maybe", {"push-out-grown-overlaps"});
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

// Issue 27: the projectile's plot (121 samples) had five empty polylines.
// Every sample is drawn, and the |p| curve is the ball's momentum m |v| from
// the CSV of the same run, at its mapped place (y axis: the series' range
// widened by 5 % each side, svg_plot.hpp).
TEST(Cli, PlotDrawsEverySampleOfTheRun) {
    const fs::path svg = tempDir() / "energy.svg", csv = tempDir() / "plot.csv";
    const Result r = fulcrum("run scenes/projectile.json --plot '" + svg.string() + "' --csv '" + csv.string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string text = readFile(svg);
    EXPECT_EQ(text.rfind("<svg", 0), 0u);
    EXPECT_NE(text.find("total"), std::string::npos);
    const auto panels = fulcrum::testing::svgPanels(text);
    ASSERT_EQ(panels.size(), 3u);
    ASSERT_EQ(panels[0].polylines.size(), 3u);  // kinetic, potential, total
    for (const auto& panel : panels) {
        for (const auto& line : panel.polylines) EXPECT_EQ(line.size(), 121u) << "one point per step 0..120";
    }
    std::vector<double> t, p;
    std::istringstream rows(readFile(csv));
    std::string row;
    std::getline(rows, row);  // header
    while (std::getline(rows, row)) {
        std::vector<double> f;
        std::istringstream cells(row);
        for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell == "ball" ? 0.0 : std::atof(cell.c_str()));
        ASSERT_EQ(f.size(), 16u) << row;
        t.push_back(f[1]);
        p.push_back(0.5 * std::sqrt(f[10] * f[10] + f[11] * f[11] + f[12] * f[12]));  // mass 0.5 kg
    }
    ASSERT_EQ(t.size(), 121u);
    const auto [lo, hi] = std::minmax_element(p.begin(), p.end());
    const fulcrum::testing::SvgMapping map(panels[1], t.front(), t.back(), *lo, *hi);
    const auto& drawn = panels[1].polylines.at(0);
    ASSERT_EQ(drawn.size(), 121u);
    for (std::size_t i = 0; i < t.size(); ++i) {
        const fulcrum::testing::SvgPoint want = map(t[i], p[i]);
        // The CSV has 9 significant digits, the SVG two decimals of a pixel.
        EXPECT_NEAR(drawn[i].x, want.x, 0.02) << "step " << i;
        EXPECT_NEAR(drawn[i].y, want.y, 0.02) << "step " << i;
    }
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

// Issue 27: `--resume DIRECTORY` aborted on an uncaught std::ios_base::failure;
// `--resume /dev/zero` and `run /dev/zero` read forever, and a FIFO blocks on
// open. Each is refused by its kind, before reading, with status 2 and one
// line naming the file; a regular file that is no snapshot by its magic.
TEST(Cli, NonRegularInputFilesAreRefusedWithStatus2) {
    const fs::path dir = tempDir() / "a_directory";
    fs::create_directories(dir);
    expectBadInput("run --resume '" + dir.string() + "'", {dir.string(), "is a directory"});
    expectBadInput("run '" + dir.string() + "'", {dir.string(), "is a directory"});
    expectBadInput("run --resume /dev/zero", {"/dev/zero", "character device"});
    expectBadInput("run /dev/zero", {"/dev/zero", "character device"});
    const fs::path fifo = tempDir() / "a_fifo";
    fs::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectBadInput("run --resume '" + fifo.string() + "'", {fifo.string(), "FIFO"});
    expectBadInput("run '" + fifo.string() + "'", {fifo.string(), "FIFO"});
    fs::remove(fifo);
    const fs::path text = writeTemp("not_a_snapshot.snap", std::string(1 << 20, 'x'));
    expectBadInput("run --resume '" + text.string() + "'", {text.string(), "not a Fulcrum snapshot"});
    expectBadInput("run --resume '" + (tempDir() / "missing.snap").string() + "'", {"missing.snap", "cannot open"});
}

// Issue 27's smaller items: each bad value gets one line that names what the
// user wrote (the option, the key) and the real limit.
TEST(Cli, OutOfRangeValuesNameTheirLimit) {
    expectBadInput("run scenes/projectile.json --steps 99999999999", {"--steps", "between 0 and 2147483647, got 99999999999"});
    // Beyond a long long: the text as written, not a clamped 9223372036854775807.
    expectBadInput("run scenes/projectile.json --steps 99999999999999999999",
                   {"--steps", "between 0 and 2147483647, got 99999999999999999999"});
    expectBadInput("run scenes/projectile.json --steps 1e5", {"--steps", "whole number", "'1e5'"});
    expectBadInput("run scenes/projectile.json --threads 99999999999999999999", {"--threads", "between 1 and 1024"});
    const fs::path steps = writeTemp("steps.json", R"({"world": {"steps": 1e20}, "bodies": []})");
    expectBadInput("run '" + steps.string() + "'", {"world.steps", "between 0 and 2147483647", "1e+20"});
    // A command-line value is the option's fault, not the scene file's.
    // Below Real's normal range (float's from 1.2e-38, double's from 2.2e-308), so each build's own values.
    constexpr bool kFloat = sizeof(fulcrum::Real) == sizeof(float);
    const std::string tinyDt = kFloat ? "1e-50" : "1e-320", tinyMass = kFloat ? "1e-45" : "5e-324";
    const std::string smallMassText = kFloat ? "1e-37" : "1e-307";
    const Result dt = fulcrum("run scenes/projectile.json --dt " + tinyDt);
    EXPECT_EQ(dt.status, 2);
    EXPECT_EQ(dt.err.rfind("fulcrum: --dt: too small", 0), 0u) << dt.err;
    EXPECT_EQ(dt.err.find("projectile.json"), std::string::npos) << dt.err;
    const fs::path sceneDt = writeTemp("dt.json", R"({"world": {"dt": )" + tinyDt + R"(}, "bodies": []})");
    expectBadInput("run '" + sceneDt.string() + "'", {"world.dt", "too small", tinyDt.c_str()});
    // A denormal mass is the mass's fault, not the inertia's.
    const fs::path mass = writeTemp("tiny_mass.json", R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "mass": )" + tinyMass + "}]}");
    expectBadInput("run '" + mass.string() + "'", {"bodies[0].mass", "too small", tinyMass.c_str()});
    const Result massErr = fulcrum("run '" + mass.string() + "'");
    EXPECT_EQ(massErr.err.find("inertia"), std::string::npos) << massErr.err;
    const fs::path smallMass =
        writeTemp("small_mass.json", R"({"bodies": [{"shape": {"type": "sphere", "radius": 0.1}, "mass": )" + smallMassText + "}]}");
    expectBadInput("run '" + smallMass.string() + "'", {"bodies[0]", "mass", "too small"});
    // Work without end: sub-steps and cloth sizes have documented limits.
    const fs::path substeps = writeTemp("substeps.json", R"({"world": {"substeps": 1000000000}, "bodies": []})");
    expectBadInput("run '" + substeps.string() + "'", {"world.substeps", "between 1 and 1000"});
    expectBadInput("run scenes/projectile.json --substeps 5000", {"--substeps", "between 1 and 1000", "5000"});
    const fs::path iterations = writeTemp("iterations.json", R"({"world": {"solver_iterations": 100000}, "bodies": []})");
    expectBadInput("run '" + iterations.string() + "'", {"world.solver_iterations", "between 1 and 1000"});
    const fs::path cloth = writeTemp("cloth.json", R"({"cloths": [{"origin": [0, 0, 0], "size": [4096, 4096]}]})");
    expectBadInput("run '" + cloth.string() + "'", {"cloths[0].size", "1000000", "16777216"});
    // --plot writes SVG, so only a .svg name is accepted (and nothing is run or written).
    const fs::path png = tempDir() / "plot.png";
    fs::remove(png);
    expectBadInput("run scenes/projectile.json --plot '" + png.string() + "'", {"--plot", png.string(), ".svg"});
    EXPECT_FALSE(fs::exists(png));
    EXPECT_EQ(fulcrum("run scenes/projectile.json --steps 2 --plot '" + (tempDir() / "upper.SVG").string() + "'").status, 0);
}

// Issue 27: bytes after a NUL were silently ignored ("{}" then anything).
TEST(Cli, NulByteInASceneIsAnErrorWithItsOffset) {
    std::string text = "{\"bodies\": []}\n";  // 15 bytes
    text.push_back('\0');
    text += "{\"bodies\": 7}";
    const fs::path nul = writeTemp("nul.json", text);
    expectBadInput("run '" + nul.string() + "'", {nul.string() + ":2:1", "NUL byte at byte offset 15"});
}

// Issue 27: an 839-character path for deep nesting. The message keeps the
// path's first and last components and stays one readable line.
TEST(Cli, DeeplyNestedErrorPathIsShortened) {
    std::string shape = R"({"type": "sphere", "radius": -1})";
    for (int i = 0; i < 12; ++i) shape = R"({"type": "compound", "children": [{"shape": )" + shape + "}]}";
    const fs::path deep = writeTemp("deep.json", R"({"bodies": [{"shape": )" + shape + "}]}");
    const Result r = fulcrum("run '" + deep.string() + "'");
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(lineCount(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(": bodies[0].shape.children[0].shape.children[0]"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("...children[0].shape.children[0].shape.radius: "), std::string::npos) << r.err;
    EXPECT_LT(r.err.size(), deep.string().size() + 200) << r.err;
}

// Issue 27: a finite state whose reported momentum overflows float (a body
// 3e38 m from the origin, falling) printed "angular": [0, 0, null] with exit 0.
// The run stops with status 3, naming the body, the step and the time.
TEST(Cli, OverflowingMomentumStopsWith3AndNamesTheBody) {
    // Real's overflow: 3e38 m in the float build, 1.5e308 m in the double build.
    const std::string farX = sizeof(fulcrum::Real) == sizeof(float) ? "3e38" : "1.5e308";
    const fs::path far = writeTemp("far.json", R"({"world": {"steps": 10},
      "bodies": [{"name": "far", "shape": {"type": "sphere", "radius": 0.5}, "mass": 1, "position": [)" + farX + ", 2, 0]}]}");
    const Result r = fulcrum("run '" + far.string() + "' --json");
    EXPECT_EQ(r.status, 3) << r.out;
    EXPECT_EQ(lineCount(r.err), 1u) << r.err;
    for (const char* part : {"body 'far'", "angular momentum", "at step ", "t = "}) EXPECT_NE(r.err.find(part), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("null"), std::string::npos) << r.out;
    // Far but harmless: the same body 3e30 m out keeps every figure finite.
    const fs::path farOk = writeTemp("far_ok.json", R"({"world": {"steps": 10},
      "bodies": [{"name": "far", "shape": {"type": "sphere", "radius": 0.5}, "mass": 1, "position": [3e30, 2, 0]}]})");
    const Result ok = fulcrum("run '" + farOk.string() + "' --json");
    EXPECT_EQ(ok.status, 0) << ok.err;
    EXPECT_EQ(ok.out.find("null"), std::string::npos) << ok.out;
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

// --json "hits": every impact of the run faster than the hit threshold (issue
// 22's hit events, at the command line). A ball dropped 1 m onto the ground
// with no restitution hits once, at sqrt(2 g h) = 4.43 m/s: within g dt (the
// speed one step adds; the speculative contact pushes within a step of the
// touch) plus 1 %. Its normal is vertical, its point on the ground's top face.
TEST(Cli, JsonListsTheRunsHitsWithTheirApproachSpeed) {
    const fs::path scene = writeTemp("drop.json", R"({
  "world": { "gravity": [0, -9.81, 0], "dt": 0.0166667, "steps": 90 },
  "bodies": [
    { "name": "ground", "type": "static", "shape": { "type": "box", "half_extents": [5, 0.5, 5] }, "position": [0, -0.5, 0] },
    { "name": "ball", "type": "dynamic", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 1,
      "position": [0, 1.1, 0], "restitution": 0 }
  ]
})");
    const Result r = fulcrum("run '" + scene.string() + "' --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("hits"));
    ASSERT_EQ(j["hits"].size(), 1u) << r.out;
    const auto& hit = j["hits"][0];
    const double expected = std::sqrt(2 * 9.81 * 1.0), dt = 0.0166667;
    EXPECT_NEAR(hit["approach_speed"].get<double>(), expected, 9.81 * dt + 0.01 * expected);
    // The fall takes sqrt(2 h / g) = 0.45 s: step 27 or so.
    EXPECT_NEAR(hit["step"].get<double>(), std::sqrt(2 * 1.0 / 9.81) / dt, 2.0);
    EXPECT_NEAR(std::abs(hit["normal"][1].get<double>()), 1.0, 1e-4);
    EXPECT_NEAR(hit["point"][1].get<double>(), 0.0, 0.02);
    const std::set<std::string> bodies{hit["body_a"].get<std::string>(), hit["body_b"].get<std::string>()};
    EXPECT_EQ(bodies, (std::set<std::string>{"ground", "ball"}));
    EXPECT_FALSE(j.contains("hits_left_out"));
}

}  // namespace

