// Scene files: every field of the contract read into the right value, the
// defaults, and the error for each kind of bad input (path, line and reason).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "fulcrum/scene.hpp"
#include "io/scene_error_expectations.hpp"

namespace fulcrum {
namespace {

Scene parse(const std::string& text) { return parseScene(text, "test.json"); }

using test::expectError;
using test::parseError;

std::string body(const std::string& extra) {
    return R"({"bodies": [{"name": "b", "shape": {"type": "sphere", "radius": 1})" + extra + "}]}";
}

TEST(SceneParse, DefaultsOfAnEmptyScene) {
    const Scene s = parse("{}");
    const WorldDef def;
    EXPECT_EQ(s.world.gravity, def.gravity);
    EXPECT_EQ(s.world.integrator, Integrator::SemiImplicitEuler);
    EXPECT_EQ(s.world.substeps, def.substeps);
    EXPECT_EQ(s.world.sleeping, true);
    EXPECT_EQ(s.dt, Real(1) / Real(60));
    EXPECT_EQ(s.steps, 600);
    EXPECT_TRUE(s.bodies.empty());
    EXPECT_EQ(s.sourceName, "test.json");
}

TEST(SceneParse, WorldSection) {
    const Scene s = parse(R"({"world": {"gravity": [0, 0, -3.5], "dt": 0.01, "steps": 42, "substeps": 7,
        "integrator": "verlet", "sleeping": false, "solver_iterations": 3, "threads": 2}})");
    EXPECT_EQ(s.world.gravity, Vec3(0, 0, Real(-3.5)));
    EXPECT_EQ(s.dt, Real(0.01));
    EXPECT_EQ(s.steps, 42);
    EXPECT_EQ(s.world.substeps, 7);
    EXPECT_EQ(s.world.integrator, Integrator::Verlet);
    EXPECT_FALSE(s.world.sleeping);
    EXPECT_EQ(s.world.solverIterations, 3);
    EXPECT_EQ(s.world.threads, 2);
    EXPECT_EQ(parse(R"({"world": {"integrator": "explicit_euler"}})").world.integrator, Integrator::ExplicitEuler);
    EXPECT_EQ(parse(R"({"world": {"steps": 0}})").steps, 0);
}

TEST(SceneParse, EveryBodyField) {
    const Scene s = parse(R"({"bodies": [{
        "name": "crate", "type": "dynamic", "shape": {"type": "box", "half_extents": [1, 2, 3]}, "mass": 12.5,
        "inertia": [1, 2, 2.5], "position": [1, 2, 3], "orientation": [0, 1, 0, 0], "linear_velocity": [4, 5, 6],
        "angular_velocity": [7, 8, 9], "friction": 0.3, "restitution": 0.25, "linear_damping": 0.1,
        "angular_damping": 0.2, "gravity_scale": -0.5, "rolling_resistance": 0.01, "linear_drag": 0.4,
        "quadratic_drag": 0.05, "filter": {"category": 2, "mask": 4294967295, "group": -3}, "is_sensor": true,
        "is_bullet": true, "allow_sleep": false, "awake": false}]})");
    ASSERT_EQ(s.bodies.size(), 1u);
    const BodyDef& d = s.bodies[0].def;
    EXPECT_EQ(d.name, "crate");
    EXPECT_EQ(d.type, BodyType::Dynamic);
    EXPECT_EQ(s.bodies[0].shape.type, ShapeType::Box);
    EXPECT_EQ(s.bodies[0].shape.halfExtents, Vec3(1, 2, 3));
    EXPECT_EQ(d.mass, Real(12.5));
    ASSERT_TRUE(d.inertia.has_value());
    EXPECT_EQ(*d.inertia, Mat3::diagonal(Vec3(1, 2, Real(2.5))));
    EXPECT_EQ(d.position, Vec3(1, 2, 3));
    EXPECT_EQ(d.orientation, Quat(0, 1, 0, 0));
    EXPECT_EQ(d.linearVelocity, Vec3(4, 5, 6));
    EXPECT_EQ(d.angularVelocity, Vec3(7, 8, 9));
    EXPECT_EQ(d.friction, Real(0.3));
    EXPECT_EQ(d.restitution, Real(0.25));
    EXPECT_EQ(d.linearDamping, Real(0.1));
    EXPECT_EQ(d.angularDamping, Real(0.2));
    EXPECT_EQ(d.gravityScale, Real(-0.5));
    EXPECT_EQ(d.rollingResistance, Real(0.01));
    EXPECT_EQ(d.linearDrag, Real(0.4));
    EXPECT_EQ(d.quadraticDrag, Real(0.05));
    EXPECT_EQ(d.filter.category, 2u);
    EXPECT_EQ(d.filter.mask, 0xFFFFFFFFu);
    EXPECT_EQ(d.filter.group, -3);
    EXPECT_TRUE(d.isSensor);
    EXPECT_TRUE(d.isBullet);
    EXPECT_FALSE(d.allowSleep);
    EXPECT_FALSE(d.awake);
}

TEST(SceneParse, BodyDefaultsMatchBodyDef) {
    const Scene s = parse(body(""));
    const BodyDef& d = s.bodies[0].def;
    const BodyDef def;
    EXPECT_EQ(d.type, BodyType::Dynamic);
    EXPECT_EQ(d.mass, 0);
    EXPECT_EQ(d.density, def.density);
    EXPECT_EQ(d.friction, def.friction);
    EXPECT_EQ(d.restitution, def.restitution);
    EXPECT_EQ(d.gravityScale, def.gravityScale);
    EXPECT_EQ(d.orientation, Quat::identity());
    EXPECT_FALSE(d.inertia.has_value());
    EXPECT_EQ(parse(body(R"(, "density": 250)")).bodies[0].def.density, Real(250));
}

TEST(SceneParse, FullInertiaMatrix) {
    const Scene s = parse(body(R"(, "inertia": [[2, 0.1, 0], [0.1, 2, 0], [0, 0, 3]])"));
    const Mat3& m = *s.bodies[0].def.inertia;
    EXPECT_EQ(m(0, 1), Real(0.1));
    EXPECT_EQ(m(1, 0), Real(0.1));
    EXPECT_EQ(m(2, 2), Real(3));
}

TEST(SceneParse, EveryShapeType) {
    const Scene s = parse(R"({"bodies": [
        {"type": "static", "shape": {"type": "plane", "normal": [0, 2, 0], "offset": -1.5}},
        {"type": "static", "shape": {"type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,0,1]], "triangles": [[0, 2, 1]]}},
        {"shape": {"type": "sphere", "radius": 0.5}},
        {"shape": {"type": "box", "half_extents": [0.1, 0.2, 0.3]}},
        {"shape": {"type": "capsule", "radius": 0.25, "half_height": 0.75}},
        {"shape": {"type": "cylinder", "radius": 0.3, "half_height": 0.6}},
        {"shape": {"type": "convex_hull", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]]}},
        {"shape": {"type": "compound", "children": [
            {"shape": {"type": "sphere", "radius": 1}, "position": [1, 0, 0], "orientation": [0, 0, 1, 0]},
            {"shape": {"type": "box", "half_extents": [1, 1, 1]}}]}}]})");
    ASSERT_EQ(s.bodies.size(), 8u);
    const ShapeDesc& plane = s.bodies[0].shape;
    EXPECT_EQ(plane.type, ShapeType::Plane);
    EXPECT_EQ(plane.normal, Vec3(0, 2, 0));
    EXPECT_EQ(plane.offset, Real(-1.5));
    const ShapeDesc& mesh = s.bodies[1].shape;
    EXPECT_EQ(mesh.vertices.size(), 3u);
    EXPECT_EQ(mesh.vertices[1], Vec3(1, 0, 0));
    ASSERT_EQ(mesh.triangles.size(), 1u);
    EXPECT_EQ(mesh.triangles[0], (std::array<std::uint32_t, 3>{0, 2, 1}));
    EXPECT_EQ(s.bodies[2].shape.radius, Real(0.5));
    EXPECT_EQ(s.bodies[3].shape.halfExtents, Vec3(Real(0.1), Real(0.2), Real(0.3)));
    EXPECT_EQ(s.bodies[4].shape.type, ShapeType::Capsule);
    EXPECT_EQ(s.bodies[4].shape.radius, Real(0.25));
    EXPECT_EQ(s.bodies[4].shape.halfHeight, Real(0.75));
    EXPECT_EQ(s.bodies[5].shape.type, ShapeType::Cylinder);
    EXPECT_EQ(s.bodies[5].shape.halfHeight, Real(0.6));
    EXPECT_EQ(s.bodies[6].shape.points.size(), 4u);
    EXPECT_EQ(s.bodies[6].shape.points[3], Vec3(0, 0, 1));
    const ShapeDesc& compound = s.bodies[7].shape;
    ASSERT_EQ(compound.children.size(), 2u);
    EXPECT_EQ(compound.children[0].position, Vec3(1, 0, 0));
    EXPECT_EQ(compound.children[0].orientation, Quat(0, 0, 1, 0));
    EXPECT_EQ(compound.children[1].shape.type, ShapeType::Box);
    EXPECT_EQ(compound.children[1].orientation, Quat::identity());
}

TEST(SceneParse, JointsWithEveryField) {
    const Scene s = parse(R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 1}},
                                         {"name": "b", "shape": {"type": "sphere", "radius": 1}}],
      "joints": [
        {"name": "h", "type": "hinge", "body_a": "a", "body_b": "b", "anchor": [1, 2, 3], "axis": [0, 0, 1],
         "limits": [-0.5, 0.75], "motor": {"speed": 2, "max_force": 10}, "spring": {"target": 0.1, "stiffness": 5, "damping": 0.5},
         "break_force": 100, "break_torque": 50, "collide_connected": true},
        {"type": "slider", "body_b": "b", "anchor": [0, 0, 0], "axis": [1, 0, 0], "limits": [0, 2]},
        {"type": "distance", "body_a": null, "body_b": "a", "anchor": [0, 5, 0], "anchor_b": [0, 3, 0],
         "min_length": 0, "max_length": 2.5, "stiffness": 100, "damping": 3},
        {"type": "ball", "body_a": "b", "body_b": "a", "anchor": [0, 1, 0]},
        {"type": "fixed", "body_a": "a", "body_b": "b", "anchor": [0, 1, 0]},
        {"type": "cone_twist", "body_b": "a", "anchor": [0, 1, 0], "axis": [0, -1, 0], "swing_limit": 0.4, "twist_limits": [-0.2, 0.3]}]})");
    ASSERT_EQ(s.joints.size(), 6u);
    const SceneJoint& h = s.joints[0];
    EXPECT_EQ(h.def.name, "h");
    EXPECT_EQ(h.def.type, JointType::Hinge);
    EXPECT_EQ(h.bodyA, "a");
    EXPECT_EQ(h.bodyB, "b");
    EXPECT_EQ(h.def.anchor, Vec3(1, 2, 3));
    EXPECT_EQ(h.def.axis, Vec3(0, 0, 1));
    EXPECT_TRUE(h.def.hasLimits);
    EXPECT_EQ(h.def.lowerLimit, Real(-0.5));
    EXPECT_EQ(h.def.upperLimit, Real(0.75));
    EXPECT_TRUE(h.def.motor.enabled);
    EXPECT_EQ(h.def.motor.speed, Real(2));
    EXPECT_EQ(h.def.motor.maxForce, Real(10));
    EXPECT_TRUE(h.def.spring.enabled);
    EXPECT_EQ(h.def.spring.target, Real(0.1));
    EXPECT_EQ(h.def.spring.stiffness, Real(5));
    EXPECT_EQ(h.def.spring.damping, Real(0.5));
    EXPECT_EQ(h.def.breakForce, Real(100));
    EXPECT_EQ(h.def.breakTorque, Real(50));
    EXPECT_TRUE(h.def.collideConnected);
    EXPECT_EQ(s.joints[1].def.type, JointType::Slider);
    EXPECT_TRUE(s.joints[1].bodyA.empty());
    EXPECT_FALSE(s.joints[1].def.motor.enabled);
    const SceneJoint& d = s.joints[2];
    EXPECT_EQ(d.def.type, JointType::Distance);
    EXPECT_TRUE(d.bodyA.empty());
    EXPECT_EQ(d.def.anchorB, Vec3(0, 3, 0));
    EXPECT_EQ(d.def.minLength, 0);
    EXPECT_EQ(d.def.maxLength, Real(2.5));
    EXPECT_EQ(d.def.stiffness, Real(100));
    EXPECT_EQ(d.def.damping, Real(3));
    EXPECT_TRUE(std::isinf(s.joints[3].def.breakForce));
    EXPECT_EQ(s.joints[4].def.type, JointType::Fixed);
    const SceneJoint& c = s.joints[5];
    EXPECT_EQ(c.def.type, JointType::ConeTwist);
    EXPECT_EQ(c.def.swingLimit, Real(0.4));
    EXPECT_EQ(c.def.twistLower, Real(-0.2));
    EXPECT_EQ(c.def.twistUpper, Real(0.3));
}

TEST(SceneParse, SpringsRopesAndCloths) {
    const Scene s = parse(R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 1}}],
      "springs": [{"body_a": null, "body_b": "a", "anchor_a": [0, 3, 0], "anchor_b": [0, 0, 0], "rest_length": 1.5,
                   "stiffness": 20, "damping": 0.5},
                  {"body_b": "a", "anchor_a": [0, 4, 0], "anchor_b": [0, 1, 0], "stiffness": 1}],
      "ropes": [{"name": "r", "start": [0, 0, 0], "end": [0, -2, 0], "segments": 8, "particle_mass": 0.2, "radius": 0.05,
                 "pin_start": false, "pin_end": true, "attach_start": "a", "attach_end": null,
                 "stretch_compliance": 0.001, "bend_compliance": 0.1}],
      "cloths": [{"name": "c", "origin": [1, 2, 3], "u_axis": [1, 0, 0], "v_axis": [0, 1, 0], "size": [4, 5],
                  "spacing": 0.2, "particle_mass": 0.02, "radius": 0.01, "pinned": [[0, 0], [3, 4]],
                  "stretch_compliance": 0.01, "bend_compliance": 0.02}]})");
    ASSERT_EQ(s.springs.size(), 2u);
    EXPECT_TRUE(s.springs[0].bodyA.empty());
    EXPECT_EQ(s.springs[0].bodyB, "a");
    EXPECT_EQ(s.springs[0].def.anchorA, Vec3(0, 3, 0));
    EXPECT_EQ(s.springs[0].def.restLength, Real(1.5));
    EXPECT_EQ(s.springs[0].def.stiffness, Real(20));
    EXPECT_EQ(s.springs[0].def.damping, Real(0.5));
    EXPECT_EQ(s.springs[1].def.restLength, Real(3)) << "rest_length defaults to the anchors' distance";
    ASSERT_EQ(s.ropes.size(), 1u);
    const SceneRope& r = s.ropes[0];
    EXPECT_EQ(r.def.name, "r");
    EXPECT_EQ(r.def.end, Vec3(0, -2, 0));
    EXPECT_EQ(r.def.segments, 8);
    EXPECT_EQ(r.def.particleMass, Real(0.2));
    EXPECT_EQ(r.def.radius, Real(0.05));
    EXPECT_FALSE(r.def.pinStart);
    EXPECT_TRUE(r.def.pinEnd);
    EXPECT_EQ(r.attachStart, "a");
    EXPECT_TRUE(r.attachEnd.empty());
    EXPECT_EQ(r.def.stretchCompliance, Real(0.001));
    EXPECT_EQ(r.def.bendCompliance, Real(0.1));
    ASSERT_EQ(s.cloths.size(), 1u);
    const SceneCloth& c = s.cloths[0];
    EXPECT_EQ(c.def.origin, Vec3(1, 2, 3));
    EXPECT_EQ(c.def.vAxis, Vec3(0, 1, 0));
    EXPECT_EQ(c.def.size, (std::array<int, 2>{4, 5}));
    EXPECT_EQ(c.def.spacing, Real(0.2));
    ASSERT_EQ(c.def.pinned.size(), 2u);
    EXPECT_EQ(c.def.pinned[1], (std::array<int, 2>{3, 4}));
    EXPECT_EQ(c.def.bendCompliance, Real(0.02));
}

// ---------------------------------------------------------------- errors

TEST(SceneErrors, MalformedJsonGivesLineAndColumn) {
    const SceneError e = parseError("{\n  \"bodies\": [1,\n  2,,]}");
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.column(), 5);
    EXPECT_TRUE(e.path().empty());
    EXPECT_NE(e.reason().find("malformed JSON"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).rfind("test.json:3:5: malformed JSON", 0), 0u) << e.what();
    EXPECT_EQ(parseError("").line(), 1);
}

TEST(SceneErrors, WhatIsFileLinePathReason) {
    const SceneError e = parseError("{\"bodies\": [\n {\"shape\": {\"type\": \"sphere\", \"radius\": 1},\n  \"mass\": -1}]}");
    EXPECT_STREQ(e.what(), "test.json:3: bodies[0].mass: mass must be positive for a dynamic body, got -1");
}

TEST(SceneErrors, UnknownKeysNameThePathAndSuggest) {
    expectError(R"({"bodies": [{"shap": {"type": "sphere", "radius": 1}}]})", "bodies[0].shap", "did you mean 'shape'?", 1);
    expectError(R"({"wrld": {}})", "wrld", "did you mean 'world'?");
    expectError(R"({"world": {"gravity": [0,0,0], "zzzzzz": 1}})", "world.zzzzzz", "unknown key");
    expectError(R"({"bodies": [{"shape": {"type": "box", "half_extents": [1,1,1], "radius": 1}}]})", "bodies[0].shape.radius",
                "unknown key for a box shape");
    expectError(R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 1}}], "joints": [
                  {"type": "ball", "body_b": "a", "anchor": [0,0,0], "limits": [0, 1]}]})",
                "joints[0].limits", "unknown key for a ball joint");
}

TEST(SceneErrors, DuplicateKeys) {
    expectError("{\"world\": {\"dt\": 0.1,\n \"dt\": 0.2}}", "world.dt", "duplicate key", 2);
}

TEST(SceneErrors, WrongTypes) {
    expectError(R"([])", "", "must be a JSON object");
    expectError(R"({"bodies": {}})", "bodies", "expected an array, got an object");
    expectError(body(R"(, "mass": "heavy")"), "bodies[0].mass", "expected a number, got a string");
    expectError(body(R"(, "position": [1, 2])"), "bodies[0].position", "expected an array of 3 numbers");
    expectError(body(R"(, "position": [1, 2, null])"), "bodies[0].position[2]", "expected a number, got null");
    expectError(body(R"(, "is_sensor": 1)"), "bodies[0].is_sensor", "expected true or false");
    expectError(R"({"world": {"steps": 2.5}})", "world.steps", "must be an integer");
    expectError(R"({"world": {"integrator": 3}})", "world.integrator", "expected a string");
}

TEST(SceneErrors, NonFiniteNumbers) {
    expectError("{\"bodies\": [{\"shape\": {\"type\": \"sphere\", \"radius\": 1},\n \"position\": [0, 1e999, 0]}]}",
                "bodies[0].position[1]", "out of range", 2);
    // Beyond Real: 1e300 in the float build; the double build's JSON numbers all fit, so 1e999 there.
    expectError(body(std::string(R"(, "mass": )") + (sizeof(Real) == sizeof(float) ? "1e300" : "1e999")), "bodies[0].mass", "out of range");
}

TEST(SceneErrors, InvalidValues) {
    expectError(body(R"(, "mass": -1)"), "bodies[0].mass", "mass must be positive for a dynamic body, got -1");
    expectError(body(R"(, "mass": 0)"), "bodies[0].mass", "mass must be positive");
    expectError(body(R"(, "density": 0)"), "bodies[0].density", "density must be positive");
    expectError(body(R"(, "mass": 1, "density": 2)"), "bodies[0].density", "either mass or density");
    expectError(body(R"(, "orientation": [0, 0, 0, 0])"), "bodies[0].orientation", "zero length");
    expectError(body(R"(, "restitution": 1.5)"), "bodies[0].restitution", "between 0 and 1");
    expectError(body(R"(, "friction": -0.1)"), "bodies[0].friction", "must not be negative");
    expectError(body(R"(, "inertia": [1, 1, 5])"), "bodies[0].inertia", "triangle inequality");
    expectError(body(R"(, "inertia": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])"), "bodies[0].inertia", "symmetric");
    expectError(R"({"world": {"dt": 0}})", "world.dt", "dt must be positive, got 0");
    expectError(R"({"world": {"dt": -0.01}})", "world.dt", "dt must be positive");
    expectError(R"({"world": {"steps": -1}})", "world.steps", "between 0 and 2147483647");
    expectError(R"({"world": {"substeps": 0}})", "world.substeps", "between 1 and 1000");
    expectError(R"({"world": {"integrator": "rk4"}})", "world.integrator",
                "unknown integrator 'rk4' (valid: semi_implicit_euler, explicit_euler, verlet)");
    expectError(body(R"(, "type": "floating")"), "bodies[0].type", "unknown body type 'floating'");
}

TEST(SceneErrors, InvalidShapes) {
    const auto shape = [](const std::string& s) { return R"({"bodies": [{"shape": )" + s + "}]}"; };
    expectError(shape(R"({"type": "sphere", "radius": 0})"), "bodies[0].shape.radius", "radius must be positive, got 0");
    expectError(shape(R"({"type": "sphere", "radius": -2})"), "bodies[0].shape.radius", "radius must be positive");
    expectError(shape(R"({"type": "sphere"})"), "bodies[0].shape", "missing key 'radius'");
    expectError(shape(R"({"type": "box", "half_extents": [1, 0, 1]})"), "bodies[0].shape.half_extents[1]", "half extents must be positive");
    expectError(shape(R"({"type": "capsule", "radius": 1, "half_height": -1})"), "bodies[0].shape.half_height", "must be positive");
    expectError(shape(R"({"type": "cone", "radius": 1})"), "bodies[0].shape.type", "unknown shape type 'cone'");
    expectError(shape(R"({"type": "convex_hull", "points": [[0,0,0],[1,0,0],[0,1,0]]})"), "bodies[0].shape.points", "at least 4 points");
    expectError(shape(R"({"type": "compound", "children": []})"), "bodies[0].shape.children", "at least one child");
    expectError(shape(R"({"type": "compound", "children": [{"shape": {"type": "box", "half_extents": [1, -1, 1]}}]})"),
                "bodies[0].shape.children[0].shape.half_extents[1]", "must be positive");
    expectError(shape(R"({"type": "plane", "normal": [0, 1, 0]})"), "bodies[0].shape.type",
                "a plane shape can only belong to a static body, but this body is dynamic");
    expectError(R"({"bodies": [{"type": "static", "shape": {"type": "plane", "normal": [0, 0, 0]}}]})", "bodies[0].shape.normal",
                "must not be the zero vector");
    expectError(shape(R"({"type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,0,1]], "triangles": [[0,1,2]]})"),
                "bodies[0].shape.type", "a mesh shape can only belong to a static body");
    expectError(R"({"bodies": [{"type": "static", "shape": {"type": "mesh", "vertices": [[0,0,0],[1,0,0],[0,0,1]],
                  "triangles": [[0,1,3]]}}]})",
                "bodies[0].shape.triangles[0][2]", "between 0 and 2");
    expectError(R"({"bodies": [{"type": "kinematic", "shape": {"type": "compound", "children": [
                  {"shape": {"type": "plane", "normal": [0, 1, 0]}}]}}]})",
                "bodies[0].shape.type", "only belong to a static body");
}

TEST(SceneErrors, BodyNamesAndReferences) {
    const std::string two = R"({"bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 1}},
                                           {"name": "ball", "shape": {"type": "sphere", "radius": 1}}]})";
    expectError(two, "bodies[1].name", "duplicate body name 'ball'", 2);
    const std::string one = R"({"bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 1}}], )";
    expectError(one + R"("joints": [{"type": "ball", "body_b": "bal", "anchor": [0,0,0]}]})", "joints[0].body_b",
                "unknown body 'bal' (did you mean 'ball'?)");
    expectError(one + R"("joints": [{"type": "ball", "body_a": "ghost", "body_b": "ball", "anchor": [0,0,0]}]})",
                "joints[0].body_a", "unknown body 'ghost'");
    expectError(one + R"("joints": [{"type": "ball", "body_a": "ball", "body_b": "ball", "anchor": [0,0,0]}]})",
                "joints[0].body_b", "two different bodies");
    expectError(one + R"("joints": [{"type": "ball", "body_b": null, "anchor": [0,0,0]}]})", "joints[0].body_b", "must name a body");
    expectError(one + R"("joints": [{"type": "weld", "body_b": "ball"}]})", "joints[0].type", "unknown joint type 'weld'");
    expectError(one + R"("joints": [{"type": "ball", "body_b": "ball"}]})", "joints[0]", "missing key 'anchor'");
    expectError(one + R"("joints": [{"type": "hinge", "body_b": "ball", "anchor": [0,0,0], "limits": [1, -1]}]})",
                "joints[0].limits", "lower must not exceed upper");
    expectError(one + R"("joints": [{"type": "distance", "body_b": "ball", "anchor": [0,0,0], "anchor_b": [0,1,0],
                  "min_length": 2, "max_length": 1}]})",
                "joints[0].max_length", "must not be less than min_length");
    expectError(one + R"("springs": [{"body_b": "nobody", "anchor_a": [0,0,0], "anchor_b": [0,0,0], "stiffness": 1}]})",
                "springs[0].body_b", "unknown body 'nobody'");
    expectError(one + R"("springs": [{"body_b": "ball", "anchor_a": [0,0,0], "anchor_b": [0,0,0], "stiffness": -1}]})",
                "springs[0].stiffness", "must not be negative");
    expectError(one + R"("ropes": [{"start": [0,0,0], "end": [0,1,0], "attach_end": "bll"}]})", "ropes[0].attach_end",
                "unknown body 'bll'");
    expectError(one + R"("ropes": [{"start": [0,0,0], "end": [0,1,0], "segments": 0}]})", "ropes[0].segments", "between 1 and");
    expectError(one + R"("cloths": [{"origin": [0,0,0], "size": [4, 4], "pinned": [[4, 0]]}]})", "cloths[0].pinned[0][0]",
                "between 0 and 3");
    expectError(one + R"("cloths": [{"origin": [0,0,0], "u_axis": [1,0,0], "v_axis": [2,0,0]}]})", "cloths[0].v_axis",
                "must not be parallel");
}

TEST(SceneErrors, LoadReportsUnreadableFiles) {
    try {
        loadScene("/nonexistent/dir/scene.json");
        FAIL() << "no error";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file(), "/nonexistent/dir/scene.json");
        EXPECT_NE(e.reason().find("cannot open"), std::string::npos);
    }
}

// Compounds nest as deep in a scene as through the API (kMaxCompoundLevels), so
// a world of a deep compound saved as a scene loads again; one level more is
// an error at the innermost compound's path, not a crash.
TEST(SceneErrors, CompoundNestingLimit) {
    const auto nested = [](int levels) {
        std::string shape = R"({"type":"sphere","radius":1})";
        for (int i = 0; i < levels; ++i) shape = R"({"type":"compound","children":[{"shape":)" + shape + "}]}";
        return R"({"bodies":[{"shape":)" + shape + "}]}";
    };
    const Scene scene = parseScene(nested(kMaxCompoundLevels), "test.json");
    EXPECT_NO_THROW(buildWorld(scene).step(Real(1) / 60));
    const SceneError e = parseError(nested(kMaxCompoundLevels + 1));
    EXPECT_NE(e.reason().find("compounds nested deeper than 32 levels"), std::string::npos) << e.what();
    EXPECT_EQ(e.path().rfind("bodies[0].shape.children[0].shape", 0), 0u) << e.what();
}
}  // namespace
}  // namespace fulcrum
