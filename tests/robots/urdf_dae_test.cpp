// COLLADA (.dae) meshes through assimp (docs/robots.md, "Format mapping"):
// the file's unit and up axis and its nodes' transforms are applied, and the
// URDF scale on top; a dynamic link collides as the mesh's convex hull, whose
// volume, centroid and inertia are checked against the closed forms of the
// solid; a static link as its triangles; a file assimp cannot read gets the
// documented fallback with a warning naming the file, link and element. The
// meshes are the project's own, written by hand in tests/robots/meshes/.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fulcrum/urdf.hpp"
#include "fulcrum/world.hpp"

namespace {

using namespace fulcrum;
namespace fs = std::filesystem;

fs::path ownDir() { return fs::path(FULCRUM_SOURCE_DIR) / "tests" / "robots"; }

const char* kInertial = R"(<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>)";

// One link holding `collision` (and `visual`), dynamic unless fixed.
Robot loadOne(World& world, const std::string& collision, bool fixedBase, std::vector<std::string>& warnings,
              const std::string& visual = "") {
    UrdfOptions o;
    o.fixedBase = fixedBase;
    o.warn = [&](const std::string& w) { warnings.push_back(w); };
    return loadUrdfFromString(world,
                              std::string(R"(<robot name="dae"><link name="part">)") + kInertial + collision + visual +
                                  "</link></robot>",
                              (ownDir() / "inline.urdf").string(), o);
}

// A right-corner tetrahedron with legs a, b, c along x, -y and z (tetra.dae:
// 10, 20 and 30 cm written in centimetres with y up; y up becomes z, so the
// file's z leg points along -y), the URDF scale doubling x: a = 0.2, b = 0.3,
// c = 0.2 m. Its volume is abc / 6, its centroid a quarter of each leg, and
// about the centroid (unit density) I_xx = 3 V (b^2 + c^2) / 80 and so on,
// with products I_xy = -V cov(x, y), cov = +-(leg)(leg) / 80.
TEST(UrdfDae, DynamicLinkCollidesAsTheHullWithTheSolidsMassProperties) {
    World world;
    std::vector<std::string> warnings;
    const Robot r = loadOne(world, R"(<collision><geometry><mesh filename="meshes/tetra.dae" scale="2 1 1"/></geometry></collision>)",
                            false, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    const Shape& shape = world.shape(r.body("part"));
    ASSERT_EQ(shape.type(), ShapeType::ConvexHull);
    const ConvexHull& hull = shape.hull();
    const double a = 0.2, b = 0.3, c = 0.2, volume = a * b * c / 6;
    EXPECT_NEAR(hull.volume, volume, 1e-6 * volume);
    EXPECT_NEAR(hull.centroid.x, a / 4, 1e-6);
    EXPECT_NEAR(hull.centroid.y, -b / 4, 1e-6);
    EXPECT_NEAR(hull.centroid.z, c / 4, 1e-6);
    const Mat3& I = hull.unitDensityInertia;
    const double ixx = 3 * volume * (b * b + c * c) / 80, iyy = 3 * volume * (a * a + c * c) / 80,
                 izz = 3 * volume * (a * a + b * b) / 80;
    const double tol = 1e-4 * ixx;
    EXPECT_NEAR(I(0, 0), ixx, tol);
    EXPECT_NEAR(I(1, 1), iyy, tol);
    EXPECT_NEAR(I(2, 2), izz, tol);
    // cov(x, y) = a (-b) cov(u, v) with cov(u, v) = -1/80 for the unit simplex.
    EXPECT_NEAR(I(0, 1), -volume * (a * b / 80), tol);
    EXPECT_NEAR(I(0, 2), volume * (a * c / 80), tol);
    EXPECT_NEAR(I(1, 2), -volume * (b * c / 80), tol);
    EXPECT_NEAR(hull.bounds.max.x, a, 1e-6);
    EXPECT_NEAR(hull.bounds.min.y, -b, 1e-6);
    EXPECT_NEAR(hull.bounds.max.z, c, 1e-6);
}

// cube.dae: a 0.2 m cube written in metres with z up, which its node lifts
// by 0.1 m. Dynamic: the hull, V = s^3, I = V s^2 / 6 about the centre at
// z = 0.1; static: the 12 triangles as they are.
TEST(UrdfDae, CubeNodeTransformAppliedHullOrTriangles) {
    World world;
    std::vector<std::string> warnings;
    const Robot dynamic = loadOne(world, R"(<collision><geometry><mesh filename="meshes/cube.dae"/></geometry></collision>)", false,
                                  warnings);
    const Shape& hull = world.shape(dynamic.body("part"));
    ASSERT_EQ(hull.type(), ShapeType::ConvexHull);
    const double s = 0.2, volume = s * s * s;
    EXPECT_NEAR(hull.hull().volume, volume, 1e-6 * volume);
    EXPECT_NEAR(hull.hull().centroid.z, 0.1, 1e-6);
    EXPECT_NEAR(hull.hull().centroid.x, 0, 1e-6);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(hull.hull().unitDensityInertia(k, k), volume * s * s / 6, 1e-4 * volume * s * s / 6);
    EXPECT_EQ(hull.hull().vertices.size(), 8u);

    const Robot fixed = loadOne(world, R"(<collision><geometry><mesh filename="meshes/cube.dae"/></geometry></collision>)", true,
                                warnings);
    const Shape& mesh = world.shape(fixed.body("part"));
    ASSERT_EQ(mesh.type(), ShapeType::Mesh);
    EXPECT_EQ(mesh.mesh().triangles.size(), 12u);
    EXPECT_NEAR(mesh.localBounds().min.z, 0, 1e-6);
    EXPECT_NEAR(mesh.localBounds().max.z, 0.2, 1e-6);
    EXPECT_TRUE(warnings.empty());
}

// A file assimp cannot read: a collider falls back to the box of the link's
// inertia, a visual is left out; each warning names the line, the link, the
// element and the file.
TEST(UrdfDae, UnreadableFileWarnsAndFallsBack) {
    World world;
    std::vector<std::string> warnings;
    const Robot r = loadOne(world, R"(<collision><geometry><mesh filename="meshes/broken.dae"/></geometry></collision>)", false,
                            warnings, R"(<visual><geometry><mesh filename="meshes/broken.dae"/></geometry></visual>)");
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_NE(warnings[0].find("inline.urdf: line 1: link 'part', collision: mesh 'meshes/broken.dae' found at"), std::string::npos)
        << warnings[0];
    EXPECT_NE(warnings[0].find("assimp cannot read it"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("collides as the box of its inertia"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[1].find("link 'part', visual: mesh 'meshes/broken.dae' found at"), std::string::npos) << warnings[1];
    EXPECT_NE(warnings[1].find("this visual is left out"), std::string::npos) << warnings[1];
    EXPECT_EQ(world.shape(r.body("part")).type(), ShapeType::Box);
    EXPECT_TRUE(r.links[0].visuals.empty());
}

}  // namespace
