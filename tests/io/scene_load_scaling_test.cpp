// Loading a scene costs time linear in its size (issue 27: a 10,000-body file
// took 24 s because every body re-scanned the text to find its own line).
// Checked without a clock: the JSON locator counts the bytes it reads, and a
// load must read the text a bounded number of times however many bodies,
// joints and springs it holds, while every element still knows its line and
// every error still names the right path and line.
#include <gtest/gtest.h>

#include <span>
#include <string>

#include "fulcrum/scene.hpp"
#include "io/json_locator.hpp"
#include "io/scene_error_expectations.hpp"

namespace fulcrum {
namespace {

constexpr int kBodies = 2000;
// Line 1 is "{", line 2 opens the bodies: body i is on line 3 + i. Two lines
// close the bodies and open the joints, two more the springs.
constexpr int kFirstBodyLine = 3;
constexpr int kFirstJointLine = kFirstBodyLine + kBodies + 2;

// One body per line (a sphere or a box on a grid, named b<i>), then a ball
// joint and a spring between each pair of neighbours, one per line;
// `lastBody` replaces the last body's text when given.
std::string gridScene(const std::string& lastBody = "") {
    std::string text = "{\n\"bodies\": [\n";
    for (int i = 0; i < kBodies; ++i) {
        if (i > 0) text += ",\n";
        if (i == kBodies - 1 && !lastBody.empty()) {
            text += lastBody;
            continue;
        }
        const std::string shape = i % 2 == 0 ? R"({"type": "sphere", "radius": 0.4})"
                                             : R"({"type": "box", "half_extents": [0.4, 0.4, 0.4]})";
        text += "  {\"name\": \"b" + std::to_string(i) + "\", \"shape\": " + shape + ", \"mass\": 1, \"position\": [" +
                std::to_string(i % 50) + ", 0.5, " + std::to_string(i / 50) + "]}";
    }
    text += "\n],\n\"joints\": [\n";
    for (int i = 1; i < kBodies - 1; i += 2) {
        if (i > 1) text += ",\n";
        text += "  {\"type\": \"ball\", \"body_a\": \"b" + std::to_string(i - 1) + "\", \"body_b\": \"b" + std::to_string(i) +
                "\", \"anchor\": [0, 0, 0]}";
    }
    text += "\n],\n\"springs\": [\n";
    for (int i = 2; i < kBodies - 1; i += 2) {
        if (i > 2) text += ",\n";
        text += "  {\"body_a\": \"b" + std::to_string(i - 1) + "\", \"body_b\": \"b" + std::to_string(i) +
                "\", \"anchor_a\": [0, 0, 0], \"anchor_b\": [1, 0, 0], \"stiffness\": 10}";
    }
    text += "\n]\n}\n";
    return text;
}

// Bytes the locator reads while `load` runs, in units of the text's size.
template <class Load>
double passesOverText(const std::string& text, Load&& load) {
    const std::uint64_t before = detail::jsonBytesScanned();
    load();
    return static_cast<double>(detail::jsonBytesScanned() - before) / static_cast<double>(text.size());
}

// A valid file: checking it for duplicate keys and locating every element
// take a few passes over the text (two scans, one line count); re-scanning it
// per body took about kBodies of them.
constexpr double kMaxPasses = 4;

TEST(SceneLoadScaling, AValidFileIsReadAFewTimesWhateverItsSize) {
    const std::string text = gridScene();
    Scene scene;
    const double passes = passesOverText(text, [&] { scene = parseScene(text, "grid.json"); });
    EXPECT_LE(passes, kMaxPasses) << "the locator read the text " << passes << " times for " << kBodies << " bodies";
    ASSERT_EQ(scene.bodies.size(), std::size_t(kBodies));
    ASSERT_EQ(scene.joints.size(), std::size_t(kBodies / 2 - 1));
    // Each element still knows where it is (buildWorld's errors name it).
    for (int i = 0; i < kBodies; ++i) {
        const SceneLocation& where = scene.bodies[std::size_t(i)].where;
        ASSERT_EQ(where.path, "bodies[" + std::to_string(i) + "]");
        ASSERT_EQ(where.line, kFirstBodyLine + i);
        ASSERT_EQ(where.column, 3);
    }
    EXPECT_EQ(scene.joints.back().where.path, "joints[" + std::to_string(scene.joints.size() - 1) + "]");
    EXPECT_EQ(scene.joints.back().where.line, kFirstJointLine + static_cast<int>(scene.joints.size()) - 1);
    EXPECT_EQ(scene.springs.front().where.line, kFirstJointLine + static_cast<int>(scene.joints.size()) + 2);
    EXPECT_EQ(scene.joints.back().bodyB, "b" + std::to_string(kBodies - 3));
}

TEST(SceneLoadScaling, ErrorsAtTheEndOfALargeFileNameTheirPathAndLine) {
    const int lastLine = kFirstBodyLine + kBodies - 1;
    const std::string last = "bodies[" + std::to_string(kBodies - 1) + "]";
    // Found by the parser: a duplicate name (the error's own lookup adds a
    // scan and a line count to a valid file's passes), a bad value.
    const std::string duplicate = gridScene(R"(  {"name": "b7", "shape": {"type": "sphere", "radius": 1}})");
    const double passes = passesOverText(duplicate, [&] {
        test::expectError(duplicate, last + ".name", "duplicate body name 'b7' (also bodies[7])", lastLine);
    });
    EXPECT_LE(passes, kMaxPasses + 2);
    test::expectError(gridScene(R"(  {"shape": {"type": "sphere", "radius": -1}})"), last + ".shape.radius",
                      "radius must be positive", lastLine);
    // A joint naming a body that does not exist, the did-you-mean from every name.
    std::string text = gridScene();
    const std::string ref = "\"body_b\": \"b1\"";
    text.replace(text.find(ref), ref.size(), "\"body_b\": \"b1x\"");
    test::expectError(text, "joints[0].body_b", "unknown body 'b1x' (did you mean 'b1'?)", kFirstJointLine);
    // Found when the world is built: the location kept by the parser.
    const Scene scene = parseScene(
        gridScene(R"(  {"shape": {"type": "convex_hull", "points": [[0,0,0],[1,0,0],[2,0,0],[3,0,0]]}})"), "grid.json");
    try {
        (void)buildWorld(scene);
        FAIL() << "a degenerate hull was accepted";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.path(), last + ".shape");
        EXPECT_EQ(e.line(), lastLine);
        EXPECT_EQ(std::string(e.what()).rfind("grid.json:" + std::to_string(lastLine) + ": " + last + ".shape: ", 0), 0u)
            << e.what();
    }
}

TEST(SceneLoadScaling, KeysOfAHugeObjectAreCheckedForDuplicates) {
    // 40,000 keys in one object (past the linear search, into the hash set):
    // the first repeated key is the error, at its path.
    std::string text = "{\"world\": {";
    for (int i = 0; i < 40000; ++i) text += "\"k" + std::to_string(i) + "\": " + std::to_string(i) + ", ";
    test::expectError(text + "\"k5\": 0, \"k7\": 0}}", "world.k5", "duplicate key", 1);
    test::expectError(text + "\"k40000\": 0}}", "world.k0", "unknown key");  // no duplicate: the keys are checked next
    // The first duplicate while the search is still linear.
    test::expectError(R"({"world": {"dt": 0.1, "steps": 3, "dt": 0.2}})", "world.dt", "duplicate key", 1);
}

TEST(SceneLoadScaling, NumbersTooLargeForADoubleAreFoundWithOrWithoutAnExponent) {
    const std::string body = R"({"bodies": [{"shape": {"type": "sphere", "radius": )";
    test::expectError(body + "1e999}}]}", "bodies[0].shape.radius", "out of range (not a finite number)", 1);
    test::expectError(body + "1" + std::string(309, '0') + "}}]}", "bodies[0].shape.radius", "out of range (not a finite number)", 1);
    // 308 digits is a finite double (then too large for the float build's Real; the double build takes it).
    if constexpr (sizeof(Real) == sizeof(float)) {
        test::expectError(body + "1" + std::string(307, '0') + "}}]}", "bodies[0].shape.radius", "out of range for the engine's single-precision");
    }
}

TEST(JsonElementIndex, AgreesWithTheFullScanOnEveryElementAndHoldsItsText) {
    // Strings holding brackets, braces, quotes and escapes, CRLF line ends,
    // nested arrays, an empty array, a non-array member and arrays deeper
    // than the root's members (not indexed), a key written with an escape.
    const std::string text = "{\"description\": \"a [b] {c}\\\" \\\\\",\r\n \"bodies\": [ {\"name\": \"x]\"},\r\n\t"
                             "{\"a\": [[1, 2], {\"b\": \"[\"}]},\n  3, \"\\u005b\", [], null],\n"
                             "\"joints\": [],\"world\": {\"gravity\": [0, [1], 2]}, \"ropes\": [\n\n  {}], \"cl\\u006fths\": [7]}";
    const detail::JsonElementIndex index(text);
    for (const char* key : {"bodies", "joints", "ropes", "cloths"}) {
        const std::span<const detail::JsonElement> elements = index.elements(key);
        for (std::size_t i = 0; i < 7; ++i) {
            const auto full = detail::locateJsonPath(text, detail::childPath(key, i));
            ASSERT_EQ(full.has_value(), i < elements.size()) << key << "[" << i << "]";
            if (!full) continue;
            EXPECT_EQ(elements[i].where.line, full->line) << key << "[" << i << "]";
            EXPECT_EQ(elements[i].where.column, full->column) << key << "[" << i << "]";
        }
    }
    // Each element's text is its whole value, nothing around it.
    const std::span<const detail::JsonElement> bodies = index.elements("bodies");
    ASSERT_EQ(bodies.size(), 6u);
    EXPECT_EQ(bodies[0].text, R"({"name": "x]"})");
    EXPECT_EQ(bodies[1].text, R"({"a": [[1, 2], {"b": "["}]})");
    EXPECT_EQ(bodies[2].text, "3");
    EXPECT_EQ(bodies[3].text, R"("\u005b")");
    EXPECT_EQ(bodies[4].text, "[]");
    EXPECT_EQ(bodies[5].text, "null");
    EXPECT_EQ(bodies[5].where.line, 4);
    EXPECT_EQ(index.elements("ropes")[0].where.line, 7);
    EXPECT_EQ(index.elements("ropes")[0].text, "{}");
    EXPECT_EQ(index.elements("cloths")[0].where.column, 24);
    EXPECT_TRUE(index.elements("joints").empty());
    EXPECT_TRUE(index.elements("world").empty());        // an object, not an array
    EXPECT_TRUE(index.elements("gravity").empty());      // not a member of the root
    EXPECT_TRUE(index.elements("description").empty());  // a string
}

}  // namespace
}  // namespace fulcrum
