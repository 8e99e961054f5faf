// Scenes end to end: every example scene loads, load -> save -> load is exact,
// buildWorld creates what the scene describes (with engine errors re-thrown
// with the path), and a captured World continues the same motion.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fulcrum/scene.hpp"
#include "io/run.hpp"
#include "io/scene_detail.hpp"
#include "io/svg_plot.hpp"
#include "support/svg_points.hpp"

namespace fulcrum {
namespace {

std::filesystem::path sceneDir() { return std::filesystem::path(FULCRUM_SOURCE_DIR) / "scenes"; }

std::vector<std::filesystem::path> exampleScenes() {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(sceneDir())) {
        if (entry.path().extension() == ".json") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

TEST(ExampleScenes, EveryOneLoadsAndRoundTrips) {
    const auto files = exampleScenes();
    ASSERT_GE(files.size(), 6u);
    for (const auto& file : files) {
        SCOPED_TRACE(file.string());
        Scene scene;
        ASSERT_NO_THROW(scene = loadScene(file));
        EXPECT_FALSE(scene.bodies.empty());
        const Scene again = parseScene(sceneToJson(scene), "saved");
        EXPECT_TRUE(again == scene) << sceneToJson(scene);
        EXPECT_EQ(sceneToJson(again), sceneToJson(scene));
        // ... and so the same World: same bodies, masses, inertias and poses.
        const World w1 = buildWorld(scene), w2 = buildWorld(again);
        ASSERT_EQ(w1.bodyCount(), w2.bodyCount());
        const auto b1 = w1.bodies(), b2 = w2.bodies();
        for (std::size_t i = 0; i < b1.size(); ++i) {
            EXPECT_EQ(w1.mass(b1[i]), w2.mass(b2[i]));
            EXPECT_EQ(w1.localInertia(b1[i]), w2.localInertia(b2[i]));
            EXPECT_EQ(w1.transform(b1[i]), w2.transform(b2[i]));
            EXPECT_EQ(w1.linearVelocity(b1[i]), w2.linearVelocity(b2[i]));
        }
    }
}

TEST(ExampleScenes, EveryOneBuildsAWorld) {
    for (const auto& file : exampleScenes()) {
        SCOPED_TRACE(file.string());
        const Scene scene = loadScene(file);
        SceneHandles handles;
        const World world = buildWorld(scene, &handles);
        // Each character brings its capsule body (docs/characters.md).
        EXPECT_EQ(world.bodyCount(), scene.bodies.size() + scene.characters.size());
        EXPECT_EQ(handles.characters.size(), scene.characters.size());
        EXPECT_EQ(handles.vehicles.size(), scene.vehicles.size());
        EXPECT_EQ(handles.joints.size(), scene.joints.size());
        EXPECT_EQ(handles.springs.size(), scene.springs.size());
        EXPECT_EQ(world.springCount(), scene.springs.size());
    }
}

TEST(SceneRoundTrip, EveryFieldSurvivesSaveAndLoad) {
    const Scene scene = parseScene(R"({"description": "all fields",
      "world": {"gravity": [0.5, -3, 1e-7], "dt": 0.004, "steps": 17, "substeps": 3, "integrator": "verlet",
                "sleeping": false, "solver_iterations": 2, "threads": 3},
      "bodies": [
        {"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": -2}},
        {"name": "a", "shape": {"type": "compound", "children": [
            {"shape": {"type": "capsule", "radius": 0.1, "half_height": 0.3}, "position": [0.1, 0.2, 0.3], "orientation": [0.5, 0.5, 0.5, 0.5]},
            {"shape": {"type": "cylinder", "radius": 0.2, "half_height": 0.1}}]},
         "density": 321.5, "inertia": [[2, 0.1, 0], [0.1, 2, 0], [0, 0, 3]], "position": [1, 2, 3], "orientation": [0.1, 0.2, 0.3, 0.4],
         "linear_velocity": [0.1, 0.2, 0.3], "angular_velocity": [3, 2, 1], "friction": 0.1, "restitution": 0.9,
         "linear_damping": 0.3, "angular_damping": 0.4, "gravity_scale": 2, "rolling_resistance": 0.5, "linear_drag": 0.6,
         "quadratic_drag": 0.7, "filter": {"category": 8, "mask": 7, "group": -1}, "is_sensor": true, "is_bullet": true,
         "allow_sleep": false, "awake": false},
        {"name": "b", "type": "kinematic", "shape": {"type": "box", "half_extents": [0.1, 0.2, 0.3]}, "mass": 0},
        {"name": "c", "shape": {"type": "convex_hull", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]]}, "mass": 2.5},
        {"type": "static", "shape": {"type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,0,1]], "triangles": [[0,2,1]]}}],
      "joints": [
        {"name": "h", "type": "hinge", "body_a": "a", "body_b": "c", "anchor": [1, 2, 3], "axis": [0, 0, 1],
         "limits": [-0.5, 0.75], "motor": {"speed": 2, "max_force": 10}, "spring": {"target": 0.1, "stiffness": 5, "damping": 0.5},
         "break_force": 100, "break_torque": 50, "collide_connected": true},
        {"type": "distance", "body_b": "a", "anchor": [0, 5, 0], "anchor_b": [0, 3, 0], "max_length": 2.5, "stiffness": 100, "damping": 3},
        {"type": "cone_twist", "body_b": "c", "anchor": [0, 1, 0], "axis": [0, -1, 0], "swing_limit": 0.4, "twist_limits": [-0.2, 0.3]}],
      "springs": [{"body_a": "a", "body_b": "c", "anchor_a": [0, 3, 0], "anchor_b": [0, 0, 0], "rest_length": 1.5,
                   "stiffness": 20, "damping": 0.5}],
      "ropes": [{"name": "r", "start": [0, 0, 0], "end": [0, -2, 0], "segments": 8, "attach_start": "a"}],
      "cloths": [{"name": "c", "origin": [1, 2, 3], "size": [4, 5], "pinned": [[0, 0], [3, 4]]}]})",
                                   "all.json");
    const std::string saved = sceneToJson(scene);
    // Written files say which format version they are (the first key).
    EXPECT_EQ(saved.rfind("{\n  \"version\": 1,", 0), 0u) << saved.substr(0, 40);
    const Scene again = parseScene(saved, "saved.json");
    EXPECT_TRUE(again == scene) << saved;
    // The comparison itself is sharp: a one-ulp change is a difference.
    Scene changed = again;
    changed.bodies[1].def.angularDamping = std::nextafter(changed.bodies[1].def.angularDamping, Real(1));
    EXPECT_FALSE(changed == scene);
    // Files written by saveScene load back the same.
    const auto file = std::filesystem::temp_directory_path() / "fulcrum_roundtrip_test.json";
    saveScene(scene, file);
    EXPECT_TRUE(loadScene(file) == scene);
    std::filesystem::remove(file);
}

TEST(BuildWorld, CreatesBodiesWithTheSceneValues) {
    const Scene scene = parseScene(R"({"world": {"gravity": [0, 0, -2], "substeps": 2},
      "bodies": [{"name": "s", "shape": {"type": "sphere", "radius": 0.5}, "density": 100, "position": [1, 2, 3],
                  "orientation": [2, 0, 0, 0], "linear_velocity": [0, 1, 0], "friction": 0.2}]})");
    SceneHandles h;
    const World world = buildWorld(scene, &h);
    ASSERT_EQ(h.bodies.size(), 1u);
    const BodyId id = h.bodies[0];
    EXPECT_EQ(world.findBody("s"), id);
    EXPECT_EQ(world.position(id), Vec3(1, 2, 3));
    EXPECT_EQ(world.orientation(id), Quat::identity()) << "orientations are normalised when the world is built";
    EXPECT_EQ(world.linearVelocity(id), Vec3(0, 1, 0));
    EXPECT_EQ(world.friction(id), Real(0.2));
    EXPECT_EQ(world.settings().gravity, Vec3(0, 0, -2));
    EXPECT_EQ(world.settings().substeps, 2);
    // Mass from density: rho 4/3 pi r^3.
    EXPECT_NEAR(world.mass(id), 100.0 * 4.0 / 3.0 * 3.14159265 * 0.125, 1e-3);
}

TEST(BuildWorld, EngineErrorsCarryThePathAndLine) {
    // A hull's geometry (here: all points on a line) is checked by the engine's
    // quickhull when the world is built; the error still names the path and line.
    const Scene scene = parseScene("{\"bodies\": [\n{\"shape\": {\"type\": \"convex_hull\", \"points\": "
                                   "[[0,0,0],[1,0,0],[2,0,0],[3,0,0]]}}]}",
                                   "hull.json");
    try {
        (void)buildWorld(scene);
        FAIL() << "a degenerate hull was accepted";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.path(), "bodies[0].shape");
        EXPECT_EQ(e.line(), 2);
        EXPECT_EQ(e.file(), "hull.json");
        EXPECT_EQ(std::string(e.what()).rfind("hull.json:2: bodies[0].shape: ", 0), 0u) << e.what();
    }
}

TEST(CaptureScene, ContinuingFromACaptureFollowsTheSameMotion) {
    // A spring-mass oscillator (period 0.993 s): run 150 steps of 5 ms straight,
    // or 75 steps, capture, save, load, build and run 75 more. No hidden state matters here (no
    // contacts, a first-order integrator), so the two agree to float rounding
    // of the carried spring anchor: 1e-4 m.
    const Scene scene = loadScene(sceneDir() / "spring_mass.json");
    SceneHandles h;
    World straight = buildWorld(scene, &h);
    for (int i = 0; i < 150; ++i) straight.step(scene.dt);

    SceneHandles h1;
    World first = buildWorld(scene, &h1);
    for (int i = 0; i < 75; ++i) first.step(scene.dt);
    const Scene captured = parseScene(sceneToJson(captureScene(first, scene, h1)), "captured");
    SceneHandles h2;
    World second = buildWorld(captured, &h2);
    for (int i = 0; i < 75; ++i) second.step(scene.dt);

    const Vec3 a = straight.position(h.bodies[0]), b = second.position(h2.bodies[0]);
    EXPECT_LT(length(a - b), 1e-4f) << "straight y " << a.y << ", resumed y " << b.y;
    // Sanity: the block really moved (3/4 of a period of a 0.5 m oscillation).
    EXPECT_GT(std::fabs(double(a.y) - (-1.5)), 0.05);
}

TEST(CaptureScene, AnchorsTravelWithTheirBodies) {
    const Scene scene = parseScene(R"({"world": {"gravity": [0, 0, 0]},
      "bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1, "linear_velocity": [1, 0, 0]},
                 {"name": "b", "shape": {"type": "sphere", "radius": 0.1}, "mass": 1, "position": [0, 1, 0], "linear_velocity": [1, 0, 0]}],
      "springs": [{"body_a": "a", "body_b": "b", "anchor_a": [0, 0, 0], "anchor_b": [0, 1, 0], "stiffness": 10}]})");
    SceneHandles h;
    World world = buildWorld(scene, &h);
    for (int i = 0; i < 60; ++i) world.step(scene.dt);  // both drift 1 m along x at 1 m/s
    const Scene captured = captureScene(world, scene, h);
    EXPECT_NEAR(captured.springs[0].def.anchorA.x, 1.0, 1e-4);
    EXPECT_NEAR(captured.springs[0].def.anchorB.x, 1.0, 1e-4);
    EXPECT_NEAR(captured.springs[0].def.anchorB.y, 1.0, 1e-4);
    EXPECT_NEAR(captured.bodies[1].def.position.x, 1.0, 1e-4);
}

TEST(SvgPlot, TicksAreNiceAndCoverTheRange) {
    const auto ticks = detail::niceTicks(0.13, 9.7, 5);
    ASSERT_GE(ticks.size(), 4u);
    EXPECT_EQ(ticks.front(), 2.0);
    EXPECT_EQ(ticks[1] - ticks[0], 2.0);
    EXPECT_LE(ticks.back(), 9.7);
    const auto small = detail::niceTicks(-0.003, 0.0021, 5);
    ASSERT_GE(small.size(), 3u);
    EXPECT_NEAR(small[1] - small[0], 0.002, 1e-12);  // 0.0051 / 5 = 0.00102 rounds up to 2e-3
}

TEST(SvgPlot, WritesOnePolylinePerSeriesWithLegendAndEscapes) {
    std::vector<double> x, a, b;
    for (int i = 0; i <= 5000; ++i) {
        x.push_back(i * 0.01);
        a.push_back(std::sin(i * 0.01));
        b.push_back(i == 2500 ? 10.0 : 0.0);  // a one-sample spike survives the envelope
    }
    const std::string svg = detail::svgPlot("t<1>", "time (s)", x, {{"panel", "y", {{"sin", a, "#000"}, {"spike", b, "red"}}}});
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    std::size_t count = 0;
    for (std::size_t p = svg.find("<polyline"); p != std::string::npos; p = svg.find("<polyline", p + 1)) ++count;
    EXPECT_EQ(count, 2u);
    EXPECT_NE(svg.find("t&lt;1&gt;"), std::string::npos);
    EXPECT_NE(svg.find(">spike</text>"), std::string::npos);
    EXPECT_NE(svg.find("</svg>"), std::string::npos);
    EXPECT_LT(svg.size(), 200000u);

    // 5001 samples on 800 columns: every drawn point is a sample at its mapped
    // place, x never goes back, each column keeps its extremes, so the spike's
    // peak and both ends of the sine are drawn.
    const auto panels = testing::svgPanels(svg);
    ASSERT_EQ(panels.size(), 1u);
    ASSERT_EQ(panels[0].polylines.size(), 2u);
    const testing::SvgMapping map(panels[0], 0.0, 50.0, *std::min_element(a.begin(), a.end()), 10.0);
    for (std::size_t k = 0; k < 2; ++k) {
        const std::vector<double>& values = k == 0 ? a : b;
        const auto& line = panels[0].polylines[k];
        ASSERT_GE(line.size(), 800u);
        ASSERT_LE(line.size(), 1600u);
        double lastX = -1;
        for (const testing::SvgPoint& pt : line) {
            // The sample this x belongs to (x pixels are 0.14 px apart, printed to 0.01).
            const std::size_t i = static_cast<std::size_t>(std::lround((pt.x - panels[0].left) / panels[0].width * 5000));
            bool matches = false;
            for (std::size_t j = i > 0 ? i - 1 : 0; j <= std::min<std::size_t>(i + 1, 5000); ++j) {
                const testing::SvgPoint want = map(x[j], values[j]);
                matches = matches || (std::fabs(want.x - pt.x) <= 0.006 && std::fabs(want.y - pt.y) <= 0.006);
            }
            EXPECT_TRUE(matches) << "series " << k << " point " << pt.x << "," << pt.y << " is no sample";
            EXPECT_GE(pt.x, lastX);
            lastX = pt.x;
        }
    }
    const testing::SvgPoint peak = map(25.0, 10.0);
    bool peakDrawn = false;
    for (const testing::SvgPoint& pt : panels[0].polylines[1]) peakDrawn = peakDrawn || (std::fabs(pt.x - peak.x) < 0.006 && std::fabs(pt.y - peak.y) < 0.006);
    EXPECT_TRUE(peakDrawn) << "the one-sample spike must survive the envelope";
}

// Issue 27: runs of 800 steps or fewer and exactly constant series were drawn
// as empty polylines (a column's min and max being one sample drew nothing).
// Every sample of a short run is drawn once, in order, at its mapped place.
TEST(SvgPlot, ShortAndConstantSeriesDrawEverySampleWhereItBelongs) {
    for (const std::size_t n : {std::size_t{1}, std::size_t{2}, std::size_t{121}, std::size_t{800}}) {
        SCOPED_TRACE(n);
        std::vector<double> x, wave, flat, zero;
        for (std::size_t i = 0; i < n; ++i) {
            x.push_back(0.5 + 0.01 * static_cast<double>(i));
            wave.push_back(3 + std::sin(0.1 * static_cast<double>(i)));
            flat.push_back(4.25);
            zero.push_back(0.0);
        }
        const std::string svg = detail::svgPlot("t", "time (s)", x,
                                                {{"mixed", "y", {{"wave", wave, "#000"}, {"flat", flat, "red"}}},
                                                 {"constant", "y", {{"flat", flat, "red"}}},
                                                 {"zero", "y", {{"zero", zero, "blue"}}}});
        const auto panels = testing::svgPanels(svg);
        ASSERT_EQ(panels.size(), 3u);
        double lo = 4.25, hi = 4.25;
        for (double v : wave) lo = std::min(lo, v), hi = std::max(hi, v);
        const double x1 = n > 1 ? x.back() : x[0];
        // One sample: the x range is padded like a constant one, so the point is mid-frame.
        const double xLo = n > 1 ? x[0] : x[0] - 0.05, xHi = n > 1 ? x1 : x[0] + 0.05;
        const testing::SvgMapping maps[] = {{panels[0], xLo, xHi, lo, hi}, {panels[1], xLo, xHi, 4.25, 4.25}, {panels[2], xLo, xHi, 0, 0}};
        const std::vector<double>* series[3][2] = {{&wave, &flat}, {&flat, nullptr}, {&zero, nullptr}};
        for (std::size_t p = 0; p < 3; ++p) {
            for (std::size_t k = 0; k < panels[p].polylines.size(); ++k) {
                ASSERT_NE(series[p][k], nullptr);
                const auto& line = panels[p].polylines[k];
                ASSERT_EQ(line.size(), n) << "panel " << p << " series " << k;
                for (std::size_t i = 0; i < n; ++i) {
                    const testing::SvgPoint want = maps[p](x[i], (*series[p][k])[i]);
                    EXPECT_NEAR(line[i].x, want.x, 0.006) << "panel " << p << " series " << k << " sample " << i;
                    EXPECT_NEAR(line[i].y, want.y, 0.006) << "panel " << p << " series " << k << " sample " << i;
                    // Inside the frame: a constant series is drawn mid-panel, not on its edge.
                    EXPECT_GT(line[i].y, panels[p].top);
                    EXPECT_LT(line[i].y, panels[p].top + panels[p].height);
                }
            }
        }
    }
}

TEST(RunScene, OverridesAreValidated) {
    Scene scene;
    detail::RunOverrides o;
    o.dt = -1;
    EXPECT_THROW(detail::applyOverrides(scene, o), detail::OptionError);
    o = {};
    o.integrator = "rk4";
    try {
        detail::applyOverrides(scene, o);
        FAIL();
    } catch (const detail::OptionError& e) {
        EXPECT_NE(std::string(e.what()).find("semi_implicit_euler, explicit_euler, verlet"), std::string::npos);
    }
    o = {};
    o.steps = 12;
    o.substeps = 3;
    o.integrator = "verlet";
    o.dt = 0.5;
    detail::applyOverrides(scene, o);
    EXPECT_EQ(scene.steps, 12);
    EXPECT_EQ(scene.world.substeps, 3);
    EXPECT_EQ(scene.world.integrator, Integrator::Verlet);
    EXPECT_EQ(scene.dt, Real(0.5));
}

TEST(RunScene, DemoSceneIsValidAndItsChainSettlesAtTheStaticEquilibrium) {
    // The demo's damped chain (3 x 1 kg, k = 200 N/m) must come to rest where
    // each spring carries the weight below it: y3 = 2 - 6 m g / k. Tolerance
    // 1 mm: after 10 s the slowest mode has decayed by more than e^-5.
    Scene scene = detail::demoScene();
    const detail::RunResult r = detail::runScene(scene, {});
    const BodyId c = r.world.findBody("spring_chain_mass3");
    EXPECT_NEAR(r.world.position(c).y, 2 - 6 * 9.81 / 200, 1e-3);
}

}  // namespace
}  // namespace fulcrum
