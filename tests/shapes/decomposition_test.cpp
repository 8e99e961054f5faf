// Shape::convexDecomposition: a convex mesh stays one hull of its volume;
// L and U shapes made of cubes split into hulls whose volumes add up to the
// mesh's (the cuts fall on the concave corners, so exactly, to float
// rounding); a curved concave mesh (a torus) within 5 %; the
// compound's mass properties equal those of the boxes it approximates, and it
// falls and rests on a plane like them; bad meshes are errors.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "fulcrum/fulcrum.hpp"

namespace fulcrum {
namespace {

using Tri = std::array<std::uint32_t, 3>;
constexpr double kPi = std::numbers::pi;

struct TestMesh {
    std::vector<Vec3> vertices;
    std::vector<Tri> triangles;
};

// The closed surface of a union of unit cubes (cells), every face outward and
// counter-clockwise seen from outside; cells must not touch only along an edge.
TestMesh cubes(const std::set<std::tuple<int, int, int>>& cells) {
    TestMesh m;
    std::map<std::tuple<int, int, int>, std::uint32_t> index;
    const auto vertex = [&](int x, int y, int z) {
        const auto [it, fresh] = index.try_emplace({x, y, z}, static_cast<std::uint32_t>(m.vertices.size()));
        if (fresh) m.vertices.push_back({Real(x), Real(y), Real(z)});
        return it->second;
    };
    for (const auto& [x, y, z] : cells) {
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                int n[3] = {x, y, z};
                n[axis] += side ? 1 : -1;
                if (cells.count({n[0], n[1], n[2]})) continue;
                // The face's corners: u and v span it so that u x v points out.
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                int c[4][3];
                for (int k = 0; k < 4; ++k) {
                    c[k][0] = x, c[k][1] = y, c[k][2] = z;
                    c[k][axis] += side;
                }
                c[1][u] += 1;
                c[2][u] += 1, c[2][v] += 1;
                c[3][v] += 1;
                std::uint32_t q[4];
                for (int k = 0; k < 4; ++k) q[k] = vertex(c[k][0], c[k][1], c[k][2]);
                if (side) {
                    m.triangles.push_back({q[0], q[1], q[2]});
                    m.triangles.push_back({q[0], q[2], q[3]});
                } else {
                    m.triangles.push_back({q[0], q[2], q[1]});
                    m.triangles.push_back({q[0], q[3], q[2]});
                }
            }
        }
    }
    return m;
}

// The same cells as an analytic compound of unit boxes.
Shape boxes(const std::set<std::tuple<int, int, int>>& cells) {
    std::vector<CompoundChild> children;
    for (const auto& [x, y, z] : cells) {
        children.push_back({Shape::box(Vec3::splat(Real(0.5))), Transform({Real(x + 0.5), Real(y + 0.5), Real(z + 0.5)}, Quat())});
    }
    return Shape::compound(children);
}

double meshVolume(const TestMesh& m) {
    double v = 0;
    for (const Tri& t : m.triangles) {
        const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
        v += double(dot(a, cross(b, c))) / 6;
    }
    return v;
}

// A torus around y: major radius R, minor r, n x k quads.
TestMesh torus(double R, double r, int n, int k) {
    TestMesh m;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * kPi * i / n;
        for (int j = 0; j < k; ++j) {
            const double b = 2 * kPi * j / k;
            const double d = R + r * std::cos(b);
            m.vertices.push_back({Real(d * std::cos(a)), Real(r * std::sin(b)), Real(d * std::sin(a))});
        }
    }
    const auto id = [&](int i, int j) { return static_cast<std::uint32_t>((i % n) * k + (j % k)); };
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < k; ++j) {
            m.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
        }
    }
    if (meshVolume(m) < 0) {
        for (Tri& t : m.triangles) std::swap(t[1], t[2]);
    }
    return m;
}

void expectMassEqual(const MassProperties& a, const MassProperties& b, double rel) {
    EXPECT_NEAR(a.mass, b.mass, rel * b.mass);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(a.centerOfMass[i], b.centerOfMass[i], rel * 3);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(a.inertia(i, j), b.inertia(i, j), rel * b.inertia(0, 0));
}

const std::set<std::tuple<int, int, int>> kL = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0}};
const std::set<std::tuple<int, int, int>> kU = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0}, {2, 1, 0}, {2, 2, 0},
                                                {0, 0, 1}, {1, 0, 1}, {2, 0, 1}, {0, 1, 1}, {0, 2, 1}, {2, 1, 1}, {2, 2, 1}};

TEST(ConvexDecomposition, ConvexMeshIsOneHullOfItsVolume) {
    const TestMesh block = cubes({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}});
    const Shape s = Shape::convexDecomposition(block.vertices, block.triangles);
    ASSERT_EQ(s.children().size(), 1u);
    EXPECT_NEAR(s.volume(), 8, 1e-5 * 8);
    // A polyhedral sphere: convex, curved; still one hull, of the mesh's own volume.
    TestMesh ball;
    const int n = 16, k = 10;
    ball.vertices.push_back({0, 1, 0});
    for (int j = 1; j < k; ++j)
        for (int i = 0; i < n; ++i) {
            const double b = kPi * j / k, a = 2 * kPi * i / n;
            ball.vertices.push_back({Real(std::sin(b) * std::cos(a)), Real(std::cos(b)), Real(std::sin(b) * std::sin(a))});
        }
    ball.vertices.push_back({0, -1, 0});
    const auto ring = [&](int j, int i) { return static_cast<std::uint32_t>(1 + (j - 1) * n + (i % n)); };
    const auto bottom = static_cast<std::uint32_t>(ball.vertices.size() - 1);
    for (int i = 0; i < n; ++i) {
        ball.triangles.push_back({0, ring(1, i + 1), ring(1, i)});
        for (int j = 1; j < k - 1; ++j) {
            ball.triangles.push_back({ring(j, i), ring(j, i + 1), ring(j + 1, i + 1)});
            ball.triangles.push_back({ring(j, i), ring(j + 1, i + 1), ring(j + 1, i)});
        }
        ball.triangles.push_back({bottom, ring(k - 1, i), ring(k - 1, i + 1)});
    }
    ASSERT_GT(meshVolume(ball), 0);
    const Shape b = Shape::convexDecomposition(ball.vertices, ball.triangles);
    ASSERT_EQ(b.children().size(), 1u);
    EXPECT_NEAR(b.volume(), meshVolume(ball), 1e-5 * meshVolume(ball));
}

TEST(ConvexDecomposition, LAndUShapesSplitAtTheirConcaveCorners) {
    for (const auto* cells : {&kL, &kU}) {
        const TestMesh m = cubes(*cells);
        const double volume = double(cells->size());
        ASSERT_NEAR(meshVolume(m), volume, 1e-9);
        const Shape s = Shape::convexDecomposition(m.vertices, m.triangles);
        // Tolerance: 1e-5 of the volume (the hulls are exact pieces; float rounding).
        EXPECT_NEAR(s.volume(), volume, 1e-5 * volume);
        EXPECT_LE(s.children().size(), cells == &kL ? 2u : 3u);
        expectMassEqual(s.massProperties(800), boxes(*cells).massProperties(800), 1e-5);
        // Deterministic: the same input gives the same hulls.
        const Shape again = Shape::convexDecomposition(m.vertices, m.triangles);
        ASSERT_EQ(again.children().size(), s.children().size());
        for (std::size_t i = 0; i < s.children().size(); ++i) {
            EXPECT_EQ(again.children()[i].shape.hull().vertices, s.children()[i].shape.hull().vertices);
        }
    }
}

TEST(ConvexDecomposition, TorusWithinItsStatedTolerance) {
    const TestMesh m = torus(1, 0.35, 24, 12);
    const double volume = meshVolume(m);
    const Shape s = Shape::convexDecomposition(m.vertices, m.triangles);
    EXPECT_GT(s.children().size(), 4u);
    EXPECT_LE(s.children().size(), 32u);
    // Hulls of pieces of a curved surface cover it with some excess: within 5 % at
    // the defaults (12 hulls, 2.5 % when written).
    EXPECT_GE(s.volume(), volume * (1 - 1e-5));
    EXPECT_LE(s.volume(), volume * 1.05);
    // Fewer hulls allowed: a coarser cover, never more than asked for.
    ConvexDecompositionOptions few;
    few.maxHulls = 4;
    EXPECT_LE(Shape::convexDecomposition(m.vertices, m.triangles, few).children().size(), 4u);
}

TEST(ConvexDecomposition, FallsAndRestsLikeTheBoxesItApproximates) {
    const TestMesh m = cubes(kU);
    const Shape decomposition = Shape::convexDecomposition(m.vertices, m.triangles);
    // Dropped flat, and tipped by 0.4 rad about x so it lands on an edge and
    // rocks back: the decomposition and the compound of boxes side by side.
    for (const Real tilt : {Real(0), Real(0.4)}) {
        SCOPED_TRACE(tilt);
        World world{WorldDef{}};
        BodyDef ground;
        ground.type = BodyType::Static;
        ground.shape = Shape::plane({0, 1, 0}, 0);
        world.createBody(ground);
        BodyDef a;
        a.shape = decomposition;
        a.position = {0, Real(0.5), 0};
        a.orientation = Quat::fromAxisAngle({1, 0, 0}, tilt);
        const BodyId decomposed = world.createBody(a);
        BodyDef b = a;
        b.shape = boxes(kU);
        b.position = {10, Real(0.5), 0};
        const BodyId reference = world.createBody(b);
        for (int i = 0; i < 240; ++i) world.step(Real(1) / 60);
        const Transform ta = world.transform(decomposed), tb = world.transform(reference);
        // At rest on its base (the frame's y = 0 face) on the plane, upright, like the boxes.
        EXPECT_NEAR(ta.p.y, 0, 0.005);
        EXPECT_NEAR(tb.p.y, 0, 0.005);
        EXPECT_GT(rotate(ta.q, Vec3::unitY()).y, 0.9999);
        EXPECT_GT(rotate(tb.q, Vec3::unitY()).y, 0.9999);
        EXPECT_LT(length(world.linearVelocity(decomposed)), 1e-3);
        // Where it came to rest: the same within 1 cm (dropped flat: no sliding at all).
        EXPECT_NEAR(ta.p.x, tb.p.x - 10, 0.01);
        EXPECT_NEAR(ta.p.z, tb.p.z, 0.01);
        const AABB bounds = world.shape(decomposed).bounds(ta);
        EXPECT_GT(bounds.min.y, -0.005);  // not sunk into the plane
    }
}

TEST(ConvexDecomposition, BadMeshesAndOptionsAreErrors) {
    const auto message = [](auto&& f) {
        try {
            f();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::vector<Tri> open = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}};
    EXPECT_NE(message([&] { (void)Shape::convexDecomposition(v, open); }).find("convex_decomposition: the mesh is not closed"),
              std::string::npos);
    const std::vector<Tri> closed = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    EXPECT_EQ(Shape::convexDecomposition(v, closed).children().size(), 1u);
    std::vector<Tri> inverted = closed;
    for (Tri& t : inverted) std::swap(t[1], t[2]);
    EXPECT_NE(message([&] { (void)Shape::convexDecomposition(v, inverted); }).find("inside out"), std::string::npos);
    const std::vector<Tri> badIndex = {{0, 2, 9}};
    EXPECT_NE(message([&] { (void)Shape::convexDecomposition(v, badIndex); }).find("convex_decomposition: mesh:"), std::string::npos);
    ConvexDecompositionOptions o;
    o.maxHulls = 0;
    EXPECT_NE(message([&] { (void)Shape::convexDecomposition(v, closed, o); }).find("options.maxHulls"), std::string::npos);
    o = {};
    o.maxConcavity = Real(NAN);
    EXPECT_NE(message([&] { (void)Shape::convexDecomposition(v, closed, o); }).find("options.maxConcavity"), std::string::npos);
    // A mesh on a dynamic body: the error points to the decomposition.
    World world{WorldDef{}};
    BodyDef d;
    d.shape = Shape::mesh(v, closed);
    EXPECT_NE(message([&] { (void)world.createBody(d); }).find("Shape::convexDecomposition"), std::string::npos);
}

}  // namespace
}  // namespace fulcrum
