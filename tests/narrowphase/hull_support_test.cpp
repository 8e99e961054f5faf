// The hull support search (hullSupportIndex, four vertices at a time with
// SSE2) must give the scalar scan's answer exactly: the first vertex of the
// largest dot, rounded as dot() rounds it. Every hull pair's results rest on it
// (the golden hashes of tests/determinism hold only if it does).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "collision/support.hpp"
#include "fulcrum/shape.hpp"

using namespace fulcrum;

namespace {

std::uint32_t scan(const std::vector<Vec3>& v, const Vec3& d) {
    std::uint32_t best = 0;
    Real bestDot = dot(v[0], d);
    for (std::uint32_t i = 1; i < v.size(); ++i) {
        if (dot(v[i], d) > bestDot) {
            bestDot = dot(v[i], d);
            best = i;
        }
    }
    return best;
}

Vec3 randomDirection(std::mt19937& rng) {
    std::normal_distribution<Real> g(0, 1);
    return Vec3{g(rng), g(rng), g(rng)};
}

void expectScanAnswer(const ConvexHull& hull, const Vec3& d) {
    ASSERT_EQ(detail::hullSupportIndex(hull, d), scan(hull.vertices, d)) << "direction " << d.x << " " << d.y << " " << d.z;
}

}  // namespace

TEST(HullSupport, RandomHullsOfEverySizeGiveTheScanAnswer) {
    std::mt19937 rng(7);
    std::normal_distribution<Real> g(0, 1);
    // Vertex counts 4 to 40 cover every remainder of the four-vertex blocks.
    for (int points = 4; points <= 60; ++points) {
        std::vector<Vec3> cloud;
        for (int i = 0; i < points; ++i) cloud.push_back(Vec3{g(rng), g(rng), g(rng)});
        const Shape shape = Shape::convexHull(cloud);
        const ConvexHull& hull = shape.hull();
        for (int k = 0; k < 300; ++k) expectScanAnswer(hull, randomDirection(rng));
        // Directions straight at each vertex, and the axes.
        for (const Vec3& v : hull.vertices) expectScanAnswer(hull, v);
        for (const Vec3& d : {Vec3{1, 0, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}}) expectScanAnswer(hull, d);
    }
}

TEST(HullSupport, TiesGoToTheFirstVertex) {
    // A box hull has exact ties along the axes and the face diagonals: the
    // first of the tied vertices wins, whichever lane it sits in.
    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i) corners.push_back({i & 1 ? Real(1) : Real(-1), i & 2 ? Real(2) : Real(-2), i & 4 ? Real(3) : Real(-3)});
    // Two boxes stacked (12 vertices, 3 blocks), so ties span blocks.
    std::vector<Vec3> prism = corners;
    for (int i = 0; i < 4; ++i) prism.push_back({i & 1 ? Real(1) : Real(-1), Real(5), i & 2 ? Real(3) : Real(-3)});
    for (const std::vector<Vec3>* points : {&corners, &prism}) {
        const Shape shape = Shape::convexHull(*points);
        const ConvexHull& hull = shape.hull();
        for (int x = -1; x <= 1; ++x) {
            for (int y = -1; y <= 1; ++y) {
                for (int z = -1; z <= 1; ++z) {
                    if (x == 0 && y == 0 && z == 0) continue;
                    expectScanAnswer(hull, Vec3{Real(x), Real(y), Real(z)});
                    expectScanAnswer(hull, Vec3{Real(x) * Real(0.0), Real(y), Real(z) * Real(-0.0)});  // signed zeros
                }
            }
        }
    }
}

TEST(HullSupport, NonFiniteDirectionsGiveTheScanAnswer) {
    std::mt19937 rng(3);
    std::normal_distribution<Real> g(0, 1);
    std::vector<Vec3> cloud;
    for (int i = 0; i < 32; ++i) cloud.push_back(Vec3{g(rng), g(rng), g(rng)});
    const Shape shape = Shape::convexHull(cloud);
    const ConvexHull& hull = shape.hull();
    const Real inf = std::numeric_limits<Real>::infinity(), nan = std::numeric_limits<Real>::quiet_NaN();
    for (const Vec3& d : {Vec3{nan, 0, 0}, Vec3{inf, 0, 0}, Vec3{inf, -inf, 1}, Vec3{0, nan, inf}, Vec3{Real(1e30), Real(1e30), 0}}) {
        expectScanAnswer(hull, d);
    }
}

TEST(HullSupport, WithoutTheDerivedTablesTheSameAnswers) {
    // A hull from the builder carries its coordinate rows (the eight-lane
    // search where the CPU has AVX2) and its vertex-face adjacency (the
    // supporting face); a hull built by hand has neither and takes the
    // four-lane search and the face-by-face search. Both give the scan's vertex
    // and the same face, ties included (a 12-sided prism: its 12 top vertices
    // tie straight up, across lanes).
    std::mt19937 rng(17);
    std::normal_distribution<Real> g(0, 1);
    std::vector<std::vector<Vec3>> clouds;
    // From 8 points: the eight-lane search takes hulls of 8 vertices or more.
    for (int points = 8; points <= 64; points += 3) {
        std::vector<Vec3> cloud;
        for (int i = 0; i < points; ++i) cloud.push_back(Vec3{g(rng), g(rng), g(rng)});
        clouds.push_back(cloud);
    }
    std::vector<Vec3> prism;
    for (int i = 0; i < 12; ++i) {
        const Real a = Real(i) * Real(2 * 3.14159265358979 / 12);
        prism.push_back({std::cos(a), 1, std::sin(a)});
        prism.push_back({std::cos(a), -1, std::sin(a)});
    }
    clouds.push_back(prism);
    for (const std::vector<Vec3>& cloud : clouds) {
        const Shape shape = Shape::convexHull(cloud);
        const ConvexHull& hull = shape.hull();
        ASSERT_EQ(hull.vertexRows.size(), 3 * hull.vertices.size());
        ASSERT_EQ(hull.vertexFaceStart.size(), hull.vertices.size() + 1);
        ConvexHull bare = hull;
        bare.vertexRows.clear();
        bare.vertexFaceStart.clear();
        bare.vertexFaces.clear();
        detail::ConvexShape withTables, withoutTables;
        withTables.kind = withoutTables.kind = detail::ConvexKind::Hull;
        withTables.hull = &hull;
        withoutTables.hull = &bare;
        withTables.xf = withoutTables.xf = Transform{{1, 2, 3}, normalize(Quat{g(rng), g(rng), g(rng), g(rng)})};
        std::vector<Vec3> directions = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}};
        for (int k = 0; k < 200; ++k) directions.push_back(randomDirection(rng));
        for (const Vec3& d : directions) {
            expectScanAnswer(hull, d);
            ASSERT_EQ(detail::hullSupportIndex(bare, d), scan(hull.vertices, d));
            detail::SupportFace a, b;
            const Vec3 n = normalize(d);
            detail::supportingFace(withTables, n, a);
            detail::supportingFace(withoutTables, n, b);
            ASSERT_EQ(a.id, b.id);
            ASSERT_EQ(a.count, b.count);
            for (std::uint32_t i = 0; i < a.count; ++i) ASSERT_TRUE(a.points[i] == b.points[i]);
        }
    }
}

TEST(HullSupport, KnownVertexGivesTheSearchedSupportAndFace) {
    // The narrow phase hands supportingFace the vertex support(n, vertex)
    // found along the same n instead of searching again: the point, the
    // vertex and the face must be the searching calls' bit for bit, for
    // plain and rounded hulls and for the kinds that have no vertex index.
    std::mt19937 rng(29);
    std::normal_distribution<Real> g(0, 1);
    std::vector<Vec3> cloud;
    for (int i = 0; i < 32; ++i) cloud.push_back(normalize(Vec3{g(rng), g(rng), g(rng)}) * Real(2));
    const Shape shapes[] = {Shape::convexHull(cloud), Shape::roundedConvexHull(cloud, Real(0.05)),
                            Shape::box({1, 2, 3}), Shape::cylinder(Real(0.5), 1), Shape::capsule(Real(0.3), 1)};
    for (const Shape& shape : shapes) {
        for (int pose = 0; pose < 50; ++pose) {
            const Transform xf{{g(rng), g(rng), g(rng)}, normalize(Quat{g(rng), g(rng), g(rng), g(rng)})};
            const detail::ConvexShape full = detail::makeConvex(shape, xf), core = detail::makeConvexCore(shape, xf);
            for (int k = 0; k < 40; ++k) {
                const Vec3 n = normalize(randomDirection(rng));
                std::uint32_t vertex = 0;
                ASSERT_TRUE(full.support(n, vertex) == full.support(n));
                if (shape.type() == ShapeType::ConvexHull) {
                    ASSERT_EQ(vertex, detail::hullSupportIndex(shape.hull(), inverseRotate(xf.q, n)));
                } else {
                    ASSERT_EQ(vertex, detail::kNoVertex);
                }
                std::uint32_t coreVertex = 0;
                ASSERT_TRUE(core.support(n, coreVertex) == core.support(n));
                detail::SupportFace searched, known;
                detail::supportingFace(core, n, searched);
                detail::supportingFace(core, n, known, coreVertex);
                ASSERT_EQ(searched.id, known.id);
                ASSERT_EQ(searched.count, known.count);
                ASSERT_TRUE(searched.normal == known.normal);
                for (std::uint32_t i = 0; i < searched.count; ++i) ASSERT_TRUE(searched.points[i] == known.points[i]);
            }
        }
    }
}
