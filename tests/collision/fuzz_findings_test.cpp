// The narrow-phase fuzz target's findings (docs/reliability.md, "Fuzzing"),
// each with its input from fuzz/corpus/narrowphase/, against the exact
// distance or depth: closed-form where the geometry gives one (parallel
// capsules, crossed cylinders), else the largest gap over all directions of
// the shapes' closed-form support functions, found in double precision by a
// dense search over the sphere refined locally (the separating-axis dual:
// for convex shapes the distance, or minus the penetration depth, is that
// maximum).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "collision/collide_mesh.hpp"
#include "collision/epa.hpp"
#include "collision/gjk.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/support.hpp"

using namespace fulcrum;

namespace {

struct Dir {
    double x, y, z;
};

double dotD(const Dir& a, const Dir& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

Dir normalized(Dir d) {
    const double l = std::sqrt(dotD(d, d));
    return {d.x / l, d.y / l, d.z / l};
}

// v rotated by the inverse of q, in double.
Dir toLocal(const Quat& q, const Dir& v) {
    const double w = q.w, x = -double(q.x), y = -double(q.y), z = -double(q.z);
    const double tx = 2 * (y * v.z - z * v.y), ty = 2 * (z * v.x - x * v.z), tz = 2 * (x * v.y - y * v.x);
    return {v.x + w * tx + (y * tz - z * ty), v.y + w * ty + (z * tx - x * tz), v.z + w * tz + (x * ty - y * tx)};
}

// max over the shape of dot(n, p): the support function, closed form.
double supportValue(const Shape& s, const Transform& xf, const Dir& n) {
    const Dir l = toLocal(xf.q, n);
    const double centre = n.x * xf.p.x + n.y * xf.p.y + n.z * xf.p.z;
    const double radial = std::sqrt(std::max(0.0, l.x * l.x + l.z * l.z));
    switch (s.type()) {
        case ShapeType::Sphere: return centre + s.radius();
        case ShapeType::Capsule: return centre + s.halfHeight() * std::fabs(l.y) + s.radius();
        case ShapeType::Cylinder: return centre + s.halfHeight() * std::fabs(l.y) + s.radius() * radial;
        case ShapeType::Box: {
            const Vec3 h = s.halfExtents();
            return centre + h.x * std::fabs(l.x) + h.y * std::fabs(l.y) + h.z * std::fabs(l.z);
        }
        case ShapeType::ConvexHull: {
            double best = -1e300;
            for (const Vec3& v : s.hull().vertices) best = std::max(best, l.x * v.x + l.y * v.y + l.z * v.z);
            return centre + best;
        }
        default: ADD_FAILURE() << "no support function for " << toString(s.type()); return 0;
    }
}

// How far B lies beyond A along unit n: min over B minus max over A.
double gapAlong(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, const Dir& n) {
    return -supportValue(b, xb, {-n.x, -n.y, -n.z}) - supportValue(a, xa, n);
}

// The exact signed distance (negative: minus the penetration depth): the
// largest gap over all directions. 40,000 directions on a Fibonacci sphere,
// and 100,000 on the great circle at right angles to each capsule's or
// cylinder's axis and to each box axis (where the gap has a crease: |n.axis|
// in the support function, so an optimum often lies on that circle, and a
// search on the sphere stalls beside it); each refined, on its circle or on
// the sphere, by a pattern search whose step is halved when nothing improves.
Dir axisOf(const Transform& xf) {
    const Vec3 a = rotate(xf.q, Vec3{0, 1, 0});
    return normalized({a.x, a.y, a.z});
}

double exactSeparation(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb) {
    const auto gap = [&](const Dir& n) { return gapAlong(a, xa, b, xb, n); };
    constexpr int kDirections = 40000;
    double best = -1e300;
    Dir bestDir{1, 0, 0};
    for (int i = 0; i < kDirections; ++i) {
        const double y = 1 - 2 * (i + 0.5) / kDirections, r = std::sqrt(std::max(0.0, 1 - y * y));
        const double phi = 2.399963229728653 * i;
        const Dir n{r * std::cos(phi), y, r * std::sin(phi)};
        const double g = gap(n);
        if (g > best) { best = g; bestDir = n; }
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (double step = 0.02; step > 1e-12; step *= 0.5) {
        for (bool improved = true; improved;) {
            improved = false;
            for (int k = 0; k < 6 + 60; ++k) {
                Dir d = bestDir;
                if (k < 6) {
                    (k / 2 == 0 ? d.x : k / 2 == 1 ? d.y : d.z) += k % 2 ? -step : step;
                } else {
                    d = {d.x + step * u(rng), d.y + step * u(rng), d.z + step * u(rng)};
                }
                d = normalized(d);
                const double g = gap(d);
                if (g > best) { best = g; bestDir = d; improved = true; }
            }
        }
    }
    const auto creaseCircle = [&](const Dir& axis) {
        // An orthonormal pair (e1, e2) at right angles to the axis.
        Dir e1 = std::fabs(axis.x) < 0.9 ? Dir{0, -axis.z, axis.y} : Dir{axis.z, 0, -axis.x};
        e1 = normalized(e1);
        const Dir e2{axis.y * e1.z - axis.z * e1.y, axis.z * e1.x - axis.x * e1.z, axis.x * e1.y - axis.y * e1.x};
        const auto at = [&](double t) { return Dir{e1.x * std::cos(t) + e2.x * std::sin(t), e1.y * std::cos(t) + e2.y * std::sin(t),
                                                   e1.z * std::cos(t) + e2.z * std::sin(t)}; };
        constexpr int kSamples = 100000;
        double circleBest = -1e300, bestT = 0;
        for (int i = 0; i < kSamples; ++i) {
            const double t = 6.283185307179586 * i / kSamples;
            const double g = gap(at(t));
            if (g > circleBest) { circleBest = g; bestT = t; }
        }
        for (double step = 6.283185307179586 / kSamples; step > 1e-13; step *= 0.5) {
            for (bool improved = true; improved;) {
                improved = false;
                for (const double t : {bestT - step, bestT + step}) {
                    const double g = gap(at(t));
                    if (g > circleBest) { circleBest = g; bestT = t; improved = true; }
                }
            }
        }
        best = std::max(best, circleBest);
    };
    // The creases: |n.axis| of a capsule or cylinder, |n.e_k| of a box.
    for (const auto& [shape, xf] : {std::pair{&a, &xa}, std::pair{&b, &xb}}) {
        if (shape->type() == ShapeType::Capsule || shape->type() == ShapeType::Cylinder) creaseCircle(axisOf(*xf));
        if (shape->type() == ShapeType::Box) {
            for (const Vec3& k : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
                const Vec3 e = rotate(xf->q, k);
                creaseCircle(normalized({e.x, e.y, e.z}));
            }
        }
    }
    return best;
}

Quat quat(double x, double y, double z, double w) {
    return Quat{Real(w), Real(x), Real(y), Real(z)};
}

// collide in both orders: one manifold each, mirrored normals, the deepest
// point within `tol` of `depth`.
void expectDepthBothOrders(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, Real margin, double depth,
                           double tol) {
    ManifoldBuffer ab, ba;
    collide(a, xa, b, xb, margin, ab);
    collide(b, xb, a, xa, margin, ba);
    ASSERT_EQ(ab.size(), 1u);
    ASSERT_EQ(ba.size(), 1u);
    EXPECT_NEAR(ab[0].maxDepth(), depth, tol);
    EXPECT_NEAR(ba[0].maxDepth(), depth, tol);
    // The normal separates the pair by (nearly) the depth: it is the least push-out.
    const Vec3 n = ab[0].normal;
    EXPECT_NEAR(-gapAlong(a, xa, b, xb, {n.x, n.y, n.z}), depth, tol);
}

}  // namespace

// fuzz/corpus/narrowphase/parallel_thin_capsules: two parallel capsules of
// radius 2 cm and 2.7 cm whose axes are 1.25 cm apart. GJK on the full
// shapes met the origin inside a triangle 12 m long and 9 cm wide and, from
// the cancelling barycentric formula, put its closest point 0.15 mm off:
// "apart by 0.15 mm" for capsules 3.45 cm deep in each other.
TEST(FuzzFindings, ParallelThinCapsulesOverlapByTheRadiiLessTheAxisGap) {
    const Quat q = quat(-0.5, -0.5, -0.5, -0.5);
    const Shape a = Shape::capsule(Real(0x1.47ae14p-6), Real(0x1.3871eep+1));
    const Shape b = Shape::capsule(Real(0x1.bb1a0cp-6), Real(0x1.df41fep+1));
    const Transform xa{{Real(-0x1.3f998p+3), -10, -10}, q}, xb{{-10, -10, -10}, q};
    // Parallel axes overlapping along their length: the distance between the
    // axes less the radii.
    const double axisGap = double(xa.p.x) - double(xb.p.x);
    const double depth = double(a.radius()) + double(b.radius()) - axisGap;
    EXPECT_NEAR(-exactSeparation(a, xa, b, xb), depth, 1e-7);
    const detail::GjkResult g = detail::gjkDistance(detail::makeConvex(a, xa), detail::makeConvex(b, xb), true);
    EXPECT_TRUE(g.overlap) << "GJK distance " << g.distance;
    expectDepthBothOrders(a, xa, b, xb, 0, depth, 1e-5);
}

// The same geometry over a sweep: parallel capsules at random orientations
// 10 m from the origin, their axes from 1 mm to 8 cm apart. GJK on the full
// shapes is a distance of axis gap - radii, or an overlap.
TEST(FuzzFindings, GjkOnParallelCapsulesGivesTheAxisGapLessTheRadii) {
    std::mt19937 rng(26);
    std::uniform_real_distribution<Real> unit(-1, 1), gapDist(Real(0.001), Real(0.08)), len(1, 4);
    for (int trial = 0; trial < 200; ++trial) {
        const Quat q = normalize(Quat{unit(rng), unit(rng), unit(rng), unit(rng)});
        const Vec3 axis = rotate(q, Vec3{0, 1, 0});
        Vec3 side = cross(axis, Vec3{1, 0, 0});
        if (length(side) < Real(0.1)) side = cross(axis, Vec3{0, 0, 1});
        side = normalize(side);
        const Real gap = gapDist(rng), ra = Real(0.02), rb = Real(0.027);
        const Shape a = Shape::capsule(ra, len(rng)), b = Shape::capsule(rb, len(rng));
        const Vec3 at{10, -10, 10};
        const Transform xa{at + side * gap, q}, xb{at, q};
        // The axes' distance, from the poses as stored (in double), less the radii.
        const Dir d{double(xa.p.x) - xb.p.x, double(xa.p.y) - xb.p.y, double(xa.p.z) - xb.p.z};
        const Dir ax = axisOf(xa);
        const double along = dotD(d, ax);
        const Dir across{d.x - ax.x * along, d.y - ax.y * along, d.z - ax.z * along};
        const Real exact = Real(std::sqrt(dotD(across, across)) - ra - rb);
        const detail::GjkResult g = detail::gjkDistance(detail::makeConvex(a, xa), detail::makeConvex(b, xb), true);
        if (exact < Real(-1e-4)) {
            EXPECT_TRUE(g.overlap) << "trial " << trial << ": overlapping by " << -exact << ", GJK distance " << g.distance;
        } else if (exact > Real(1e-4)) {
            EXPECT_FALSE(g.overlap) << "trial " << trial;
            EXPECT_NEAR(g.distance, exact, Real(2e-5)) << "trial " << trial;
        }
    }
}

// fuzz/corpus/narrowphase/small_hull_inside_capsule: a 3 cm hull at the
// centre of a capsule of radius 3.2 m. GJK on the cores (the capsule's axis
// through the hull) ended on a duplicate support point after the same
// cancelling triangle formula left it 3.9 mm off, and called the cores apart:
// a gap of 0.14 m. Then EPA on the full, curved shapes ran out of vertices
// 1.7 mm short of the depth; EPA now runs on the cores and adds the radii.
TEST(FuzzFindings, SmallHullInsideACapsuleIsAsDeepAsTheCapsuleAroundIt) {
    const std::vector<Vec3> points{{Real(-0x1.47ae14p-6), Real(-0x1.47ae14p-6), Real(-0x1.59b48cp-8)},
                                   {Real(0x1.7eef98p-7), Real(0x1.7eef98p-7), Real(0x1.7eef98p-7)},
                                   {Real(-0x1.55d0b2p-7), Real(0x1.51ef64p-7), Real(-0x1.47ae14p-6)},
                                   {Real(-0x1.53600cp-7), Real(-0x1.55d0b2p-7), Real(-0x1.55d0b2p-7)}};
    const Shape hull = Shape::convexHull(points);
    const Shape capsule = Shape::capsule(Real(0x1.961dccp+1), Real(0x1.961dccp+1));
    const Real c = Real(0x1.75f5f4p+2);
    const Transform at{{c, c, c}, quat(0.5, 0.5, 0.5, 0.5)};
    const double depth = -exactSeparation(hull, at, capsule, at);
    // The capsule's radius plus the hull's reach back across the axis.
    EXPECT_GT(depth, double(capsule.radius()));
    EXPECT_LT(depth, double(capsule.radius()) + 0.02);
    const detail::GjkResult cores = detail::gjkDistance(detail::makeConvex(hull, at), detail::makeConvex(capsule, at), false);
    EXPECT_TRUE(cores.overlap) << "core distance " << cores.distance;
    const detail::PenetrationResult p = detail::epaPenetration(detail::makeConvex(hull, at), detail::makeConvex(capsule, at));
    ASSERT_TRUE(p.valid);
    EXPECT_NEAR(p.depth, depth, 1e-5);
    expectDepthBothOrders(hull, at, capsule, at, Real(0.396078438), depth, 1e-5);
}

// fuzz/corpus/narrowphase/crossed_cylinders_depths and _same_point: EPA on
// two cylinders added support points a few micrometres off the faces they
// replaced (the rims are curved), its visibility tests then cut a horizon
// that was not a loop and the polytope stopped enclosing the origin: depths
// of 1.0 cm and 4.2 cm for the two orders of one pair (exact 4.19 cm), of
// 3 mm, 2.2 cm or -1.6 m for cylinders 2.6 m deep in each other.
TEST(FuzzFindings, CrossedCylindersHaveOneDepthInBothOrders) {
    const Shape a = Shape::cylinder(Real(0x1.2d2868p+1), Real(0x1.c8594cp-1));
    const Shape b = Shape::cylinder(Real(0x1.38b18ap-1), 4);
    const Transform xa{{10, 10, 10}, quat(0.5, 0.5, 0.5, 0.5)};
    const Transform xb{{10, 10, Real(0x1.f2067p+2)}, quat(0x1.57b132p-1, 0x1.fd77a8p-2, -0x1.0c0358p-1, 0x1.55bf72p-3)};
    const double depth = -exactSeparation(a, xa, b, xb);
    EXPECT_NEAR(depth, 0.04191, 1e-4);
    expectDepthBothOrders(a, xa, b, xb, Real(0.411429018), depth, 1e-4);
}

TEST(FuzzFindings, CylindersCrossingAtOnePointHaveOneDepthInBothOrders) {
    const Shape a = Shape::cylinder(Real(0x1.2d2868p+1), Real(0x1.88aaf8p-1));
    const Shape b = Shape::cylinder(Real(0x1.38b18ap-1), Real(0x1.fe4636p+1));
    const Transform xa{{10, 10, 10}, quat(0.5, 0.5, 0.5, 0.5)};
    const Transform xb{{10, 10, 10}, quat(0x1.71e8fcp-3, 0x1.75544ap-2, -0x1.9c30eap-2, -0x1.a3d93ep-1)};
    const double depth = -exactSeparation(a, xa, b, xb);
    EXPECT_NEAR(depth, 2.6176, 1e-3);
    expectDepthBothOrders(a, xa, b, xb, Real(0.000221255817), depth, 1e-4);
}

// Two long cylinders crossing at right angles, one's axis `s` above the
// other's: the least push-out is along the line between the axes, by
// rA + rB - s (the other ways out are the lengths, metres). At random
// orientations 10 m from the origin, both orders.
TEST(FuzzFindings, PerpendicularCylindersOverlapByTheRadiiLessTheAxisDistance) {
    std::mt19937 rng(22);
    std::uniform_real_distribution<Real> unit(-1, 1);
    const Real ra = Real(0.5), rb = Real(0.3);
    const Shape a = Shape::cylinder(ra, 3), b = Shape::cylinder(rb, 3);
    for (int trial = 0; trial < 20; ++trial) {
        const Quat q = normalize(Quat{unit(rng), unit(rng), unit(rng), unit(rng)});
        const Real s = Real(0.7) * static_cast<Real>(trial % 5) / 4;  // 0 (one centre) to 0.7 m
        // A along the frame's x, B along its z, B above A along its y.
        const Quat qa = q * Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963)), qb = q * Quat::fromAxisAngle({1, 0, 0}, Real(1.5707963));
        const Vec3 at{-10, 10, 10};
        const Transform xa{at, qa}, xb{at + rotate(q, Vec3{0, s, 0}), qb};
        const double depth = double(ra) + double(rb) - double(s);
        EXPECT_NEAR(-exactSeparation(a, xa, b, xb), depth, 1e-5) << "trial " << trial;
        expectDepthBothOrders(a, xa, b, xb, Real(0.05), depth, 1e-4);
    }
}

// Found by the runs that checked these fixes (empty corpus, seeds 2 and 4),
// in fuzz/corpus/narrowphase/: cylinder_near_thin_plate, box_near_flat_capsule.
// GJK built a nearly flat tetrahedron (the new support point between two
// earlier ones on a curved rim) and its single-precision side tests put the
// origin inside: "overlapping" for shapes 12 cm and 52 cm apart.
TEST(FuzzFindings, ShapesApartAreApartWhenGjkBuildsAFlatTetrahedron) {
    {
        const Shape cylinder = Shape::cylinder(Real(0x1.7b79f6p+1), Real(0x1.0acb2p+0));
        const Shape plate = Shape::box({Real(0x1.9b0d76p+1), Real(0x1.50a298p-6), Real(0x1.70bfb8p+1)});
        const Transform xa{{Real(-0x1.9bc3ap+0), Real(-0x1.b5ed36p+2), Real(-0x1.35f234p+1)},
                           quat(-0x1.35071ep-1, 0x1.d2a0bcp-2, -0x1.3527a4p-4, -0x1.4cbdep-1)};
        const Transform xb{{Real(0x1.774c78p+1), Real(-0x1.3aaebap+2), Real(-0x1.e11eep+1)},
                           quat(0x1.a5e796p-2, -0x1.4207aep-1, 0x1.048776p-1, -0x1.ad408cp-2)};
        const double exact = exactSeparation(cylinder, xa, plate, xb);
        EXPECT_NEAR(exact, 0.1219, 1e-3);
        const detail::GjkResult g = detail::gjkDistance(detail::makeConvex(cylinder, xa), detail::makeConvex(plate, xb), true);
        EXPECT_FALSE(g.overlap);
        EXPECT_NEAR(g.distance, exact, 1e-5);
        ManifoldBuffer out;
        collide(cylinder, xa, plate, xb, Real(0x1.ef19fp-4), out);  // a margin of 12.09 cm: no contact
        EXPECT_TRUE(out.empty());
    }
    {
        const Shape box = Shape::box({Real(0x1.27d53cp+1), Real(0x1.f68cc4p+0), Real(0x1.9138p-1)});
        const Shape pill = Shape::capsule(Real(0x1.f6a0aap+0), Real(0x1.47ae14p-6));
        const Transform xa{{Real(-0x1.5dfedep+2), -10, -10}, quat(-0x1.273624p-1, -0x1.2d475ap-8, -0x1.2784cap-1, -0x1.2811e2p-1)};
        const Transform xb{{-10, -10, -10}, quat(-0.5, -0.5, -0.5, -0.5)};
        const double exact = exactSeparation(box, xa, pill, xb);
        EXPECT_NEAR(exact, 0.5198, 1e-3);
        const detail::GjkResult g = detail::gjkDistance(detail::makeConvex(box, xa), detail::makeConvex(pill, xb), true);
        EXPECT_FALSE(g.overlap);
        EXPECT_NEAR(g.distance, exact, 1e-5);
    }
}

// fuzz/corpus/narrowphase/parallel_capsules_same_centre (the same runs, seed
// 4): two parallel capsules sharing their centre. The closest points of their
// axes came out of a single-precision formula that cancels for parallel
// segments 0.16 mm apart in a made-up direction, and the two orders measured
// 4.70 and 4.87 cm; the axes intersect, so the depth is the radii's sum.
TEST(FuzzFindings, ParallelCapsulesSharingTheirCentreOverlapByTheirRadii) {
    const Shape a = Shape::capsule(Real(0x1.47ae14p-6), Real(0x1.3871eep+1));
    const Shape b = Shape::capsule(Real(0x1.bb1a0cp-6), Real(0x1.df41fep+1));
    const Real c = Real(-0x1.55556p-1);
    const Transform xa{{c, c, c}, quat(-0.5, -0.5, -0.5, -0.5)};
    const Transform xb{{c, c, c}, quat(-0x1.8172b4p-5, -0x1.695b8ap-1, -0x1.691d6ep-1, -0x1.8172b4p-5)};
    const double depth = double(a.radius()) + double(b.radius());
    EXPECT_NEAR(-exactSeparation(a, xa, b, xb), depth, 1e-6);
    expectDepthBothOrders(a, xa, b, xb, Real(0x1.dddddep-3), depth, 1e-5);
}

namespace {

// How far box B, moved along -n (unit, from A to B), travels before it
// touches box A, in double: the first contact of two boxes under translation
// is a corner of one entering the other (a ray against the other box's three
// slabs) or an edge of each crossing (a 3 x 3 system in the two edge
// parameters and the travel). Infinity when B passes A by.
struct BoxD {
    Dir centre, axis[3];
    double half[3];
};

BoxD boxD(const Shape& s, const Transform& xf) {
    BoxD b{{xf.p.x, xf.p.y, xf.p.z}, {}, {s.halfExtents().x, s.halfExtents().y, s.halfExtents().z}};
    for (int j = 0; j < 3; ++j) {
        // The box's axes are the columns of its rotation R; toLocal gives
        // R^T e_j, row j of R: component j of each axis.
        const Dir row = toLocal(xf.q, {j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0, j == 2 ? 1.0 : 0.0});
        (j == 0 ? b.axis[0].x : j == 1 ? b.axis[0].y : b.axis[0].z) = row.x;
        (j == 0 ? b.axis[1].x : j == 1 ? b.axis[1].y : b.axis[1].z) = row.y;
        (j == 0 ? b.axis[2].x : j == 1 ? b.axis[2].y : b.axis[2].z) = row.z;
    }
    return b;
}

Dir plus(const Dir& a, const Dir& b, double s = 1) { return {a.x + s * b.x, a.y + s * b.y, a.z + s * b.z}; }
Dir crossD(const Dir& a, const Dir& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

Dir cornerOf(const BoxD& b, int k) {
    Dir c = b.centre;
    for (int i = 0; i < 3; ++i) c = plus(c, b.axis[i], (k >> i & 1) ? b.half[i] : -b.half[i]);
    return c;
}

double rayIntoBox(const Dir& origin, const Dir& dir, const BoxD& b) {
    double lo = 0, hi = 1e300;
    const Dir r = plus(origin, b.centre, -1);
    for (int i = 0; i < 3; ++i) {
        const double s = dotD(r, b.axis[i]), v = dotD(dir, b.axis[i]);
        if (std::fabs(v) < 1e-15) {
            if (std::fabs(s) > b.half[i]) return 1e300;
            continue;
        }
        const double t0 = (-b.half[i] - s) / v, t1 = (b.half[i] - s) / v;
        lo = std::max(lo, std::min(t0, t1));
        hi = std::min(hi, std::max(t0, t1));
        if (lo > hi) return 1e300;
    }
    return lo;
}

double boxTravelAlong(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, const Vec3& normal) {
    const BoxD A = boxD(a, xa), B = boxD(b, xb);
    const Dir n{normal.x, normal.y, normal.z}, back{-n.x, -n.y, -n.z};
    double best = 1e300;
    for (int k = 0; k < 8; ++k) {
        best = std::min(best, rayIntoBox(cornerOf(B, k), back, A));
        best = std::min(best, rayIntoBox(cornerOf(A, k), n, B));
    }
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const Dir ea = plus({0, 0, 0}, A.axis[i], 2 * A.half[i]), eb = plus({0, 0, 0}, B.axis[j], -2 * B.half[j]);
            const double det = dotD(ea, crossD(eb, n));
            if (std::fabs(det) < 1e-12) continue;
            for (int ka = 0; ka < 8; ++ka) {
                for (int kb = 0; kb < 8; ++kb) {
                    if ((ka >> i & 1) || (kb >> j & 1)) continue;
                    // s ea + u (-edge of B) + t n = B's edge start - A's edge start (Cramer).
                    const Dir r = plus(cornerOf(B, kb), cornerOf(A, ka), -1);
                    const double s = dotD(r, crossD(eb, n)) / det, u = dotD(ea, crossD(r, n)) / det,
                                 t = dotD(ea, crossD(eb, r)) / det;
                    if (s >= 0 && s <= 1 && u >= 0 && u <= 1 && t >= 0) best = std::min(best, t);
                }
            }
        }
    }
    return best;
}

}  // namespace

// fuzz/corpus/narrowphase/box_box_gap_exceeds_distance (docs/reliability.md):
// two boxes 0.4484 m apart get a speculative point 0.4668 m from A's face.
// The part of B nearest A lies outside that face, so the gap along the
// normal exceeds the distance; but B, moved along the normal, first touches
// A after exactly that gap. The speculative contact is right, and so the
// fuzz target checks the gap against this travel, not the distance.
TEST(FuzzFindings, BoxGapAlongAFaceNormalIsTheTravelBeforeTouching) {
    const Shape a = Shape::box({Real(0x1.aaff04p+1), Real(0x1.427cfap-1), Real(0x1.89adcp+1)});
    const Shape b = Shape::box({Real(0x1.4c6e4cp+1), Real(0x1.04773cp+0), Real(0x1.9b2756p+1)});
    const Transform xa{{Real(-0x1.4p+3), Real(-0x1.3ffd8p+3), Real(-0x1.8b9a0cp+2)},
                       quat(-0x1.06e63cp-2, 0x1.eea5a8p-2, 0x1.131f44p-3, 0x1.a70afcp-1)};
    const Transform xb{{Real(-0x1.12fe92p+2), Real(-0x1.159796p+2), Real(-0x1.a66126p+2)},
                       quat(0x1.3e241ap-1, -0x1.f68544p-3, -0x1.a3351p-2, 0x1.3e241ap-1)};
    ManifoldBuffer out;
    collide(a, xa, b, xb, Real(0.5), out);
    ASSERT_EQ(out.size(), 1u);
    const double travel = boxTravelAlong(a, xa, b, xb, out[0].normal);
    EXPECT_NEAR(travel, 0.4668, 1e-4);
    EXPECT_NEAR(-out[0].maxDepth(), travel, 1e-4);
    EXPECT_NEAR(exactSeparation(a, xa, b, xb), 0.4484, 1e-4);
}

// Found while measuring the one above (random box pairs against
// boxTravelAlong): a thin plate whose corner lies beyond the edge of A's
// reference face. Clipping kept only points of B's face over A's face, 0.465 m
// along the normal, while the plate's corner meets A's edge after 0.142 m:
// the solver would have let the plate 0.32 m into A in one step. The manifold
// now carries the first touch (collide_box.cpp, firstTouchAlong).
TEST(FuzzFindings, BoxGapNeverExceedsTheTravelBeforeTouching) {
    const Shape a = Shape::box({Real(0x1.c6ab3ap+0), Real(0x1.3e09d8p-1), Real(0x1.de919p+1)});
    const Shape b = Shape::box({Real(0x1.f5799ep-2), Real(0x1.7292e2p+0), Real(0x1.c4ad7cp-3)});
    const Transform xa{{Real(0x1.fee1bep+1), Real(-0x1.249338p-1), Real(0x1.21ec78p+1)},
                       quat(-0x1.e681bp-2, 0x1.2deb34p-2, 0x1.92f856p-1, -0x1.0ad1fcp-2)};
    const Transform xb{{Real(0x1.6011acp+1), Real(0x1.444f88p+1), Real(0x1.4c30ap+1)},
                       quat(0x1.d20ad4p-2, 0x1.529588p-2, 0x1.89db84p-1, -0x1.363c6ep-2)};
    for (const bool swapped : {false, true}) {
        ManifoldBuffer out;
        if (swapped) {
            collide(b, xb, a, xa, Real(0.5), out);
        } else {
            collide(a, xa, b, xb, Real(0.5), out);
        }
        ASSERT_EQ(out.size(), 1u);
        const double travel = swapped ? boxTravelAlong(b, xb, a, xa, out[0].normal) : boxTravelAlong(a, xa, b, xb, out[0].normal);
        EXPECT_NEAR(-out[0].maxDepth(), travel, 1e-4) << (swapped ? "(b, a)" : "(a, b)");
    }
    ManifoldBuffer out;
    collide(a, xa, b, xb, Real(0.5), out);
    EXPECT_NEAR(boxTravelAlong(a, xa, b, xb, out[0].normal), 0.1424, 1e-4);
    EXPECT_NEAR(exactSeparation(a, xa, b, xb), 0.0792, 1e-4);
}

// Found the same way (random box-cylinder pairs, the fuzz target's rule): a
// thin disk whose rim comes nearest a box just beyond the edge of the box's
// face. The face normal was the contact normal (it separates as well as
// GJK's), the rim's nearest point was not over the face, and the clipped cap
// (a square) was 0.305 m from the face where the shapes are 0.2868 m apart
// and meet after that along the face normal (its curved rim just inside the
// edge): GJK's closest points now join the clipped ones
// (collide_convex.cpp). The gap is at most the exact distance (itself at most
// the travel) and at least the face axis's separation.
TEST(FuzzFindings, BoxFaceGapNeverExceedsACylinderRimsDistance) {
    const Shape box = Shape::box({Real(0x1.40e5e6p+1), Real(0x1.959788p+0), Real(0x1.947914p+0)});
    const Shape disk = Shape::cylinder(Real(0x1.67493ep+0), Real(0x1.a0825cp-4));
    const Transform xa{{Real(0x1.ecdcp-3), Real(0x1.f60bp-3), Real(0x1.6a86f4p+1)},
                       quat(0x1.684688p-2, -0x1.298672p-1, 0x1.b90c32p-4, -0x1.73a9dcp-1)};
    const Transform xb{{Real(0x1.ca553p+0), Real(-0x1.5b2688p+1), Real(0x1.2043fp+1)},
                       quat(-0x1.e0028ep-1, -0x1.bdfa26p-6, 0x1.769f6cp-4, -0x1.569f24p-2)};
    const double exact = exactSeparation(box, xa, disk, xb);
    EXPECT_NEAR(exact, 0.2868, 1e-4);
    for (const bool swapped : {false, true}) {
        ManifoldBuffer out;
        if (swapped) {
            collide(disk, xb, box, xa, Real(0.5), out);
        } else {
            collide(box, xa, disk, xb, Real(0.5), out);
        }
        ASSERT_EQ(out.size(), 1u);
        const Vec3 n = swapped ? -out[0].normal : out[0].normal;
        const double faceSeparation = gapAlong(box, xa, disk, xb, {n.x, n.y, n.z});
        EXPECT_LE(-out[0].maxDepth(), exact + 1e-3) << (swapped ? "(disk, box)" : "(box, disk)");
        EXPECT_GE(-out[0].maxDepth(), faceSeparation - 1e-5) << (swapped ? "(disk, box)" : "(box, disk)");
    }
}

// fuzz/corpus/narrowphase/box_box_orders_take_their_own_faces (the run that
// checked the fixes above, seed 2): two boxes 0.238 m apart. collide(a, b)
// takes a face of A as the normal and collide(b, a) one of B, 23 degrees
// apart, with gaps of 0.2565 m and 0.2453 m: the target wanted one gap for
// both orders, but each is exactly the travel along its own normal.
TEST(FuzzFindings, BoxPairOrdersApartEachGiveTheTravelAlongTheirNormal) {
    const Shape a = Shape::box({Real(0x1.48c3a6p+0), Real(0x1.48c3a6p+0), Real(0x1.48c3a6p+0)});
    const Shape b = Shape::box({Real(0x1.48c3a6p+0), Real(0x1.483c54p+0), Real(0x1.c977dep-1)});
    const Transform xa{{Real(-0x1.941414p+2), Real(-0x1.1c139cp+2), Real(-0x1.941414p+2)},
                       quat(-0x1.f4f034p-2, -0x1.f521cap-2, -0x1.df8bb6p-3, -0x1.5da5a8p-1)};
    const Transform xb{{Real(-0x1.d2d2d4p+1), Real(-0x1.d2d2d4p+1), Real(-0x1.d2d2d4p+1)},
                       quat(0x1.2114f6p-2, 0x1.2114f6p-2, -0x1.b89a26p-1, -0x1.43e934p-2)};
    const Real margin = Real(0x1.535354p-2);
    ManifoldBuffer ab, ba;
    collide(a, xa, b, xb, margin, ab);
    collide(b, xb, a, xa, margin, ba);
    ASSERT_EQ(ab.size(), 1u);
    ASSERT_EQ(ba.size(), 1u);
    EXPECT_NEAR(exactSeparation(a, xa, b, xb), 0.2378, 1e-4);
    EXPECT_NEAR(-ab[0].maxDepth(), boxTravelAlong(a, xa, b, xb, ab[0].normal), 1e-4);
    EXPECT_NEAR(-ba[0].maxDepth(), boxTravelAlong(b, xb, a, xa, ba[0].normal), 1e-4);
    const Real alignment = dot(ab[0].normal, ba[0].normal);  // -1: mirrored
    EXPECT_GT(alignment, Real(-0.95));  // 23 degrees apart
    EXPECT_LT(alignment, Real(-0.9));
}

// Found by a 10^6-input run of fuzz/snapshot_fuzz.cpp: a compound body 1e13 m
// across over a two-triangle mesh gave a mesh contact candidate whose normal
// had lost its unit length. Grouping picked it as the seed of a group, it
// failed its own "same normal" test (n . n < 0.999), stayed unused and was
// picked again for ever (the step hung). Grouping now always takes the seed,
// so each candidate is used once: two candidates, one with a normal 0.5 long,
// give two manifolds (the normals differ), each with its own point.
TEST(FuzzFindings, MeshContactGroupingEndsWhenANormalIsNotUnit) {
    std::vector<detail::MeshContactCandidate> scratch(2);
    scratch[0].contact = {{0, 0, 0}, Real(0.01), 1};
    scratch[0].normal = {0, Real(0.5), 0};  // not unit: the seed (deepest)
    scratch[1].contact = {{1, 0, 0}, Real(0.005), 2};
    scratch[1].normal = {0, 1, 0};
    ManifoldBuffer out;
    detail::groupTriangleContacts(scratch, Real(0.02), out);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].pointCount, 1u);
    EXPECT_NEAR(out[0].points[0].depth, 0.01, 1e-7);
    EXPECT_EQ(out[1].pointCount, 1u);
    EXPECT_NEAR(out[1].points[0].depth, 0.005, 1e-7);
}

// fuzz/corpus/narrowphase/tilted_cylinder_cap_near_plane (CI's run of
// 2026-11-28): a cylinder tilted within the cap band (axis . n >= 0.95)
// whose rim came within the margin of a plane while the cap's inscribed
// square, 0.29 r sin(tilt) higher where the rim is lowest between two
// corners, was beyond it: no manifold at all, so nothing would have held a
// fast cylinder back. The rim's lowest point is now kept when no corner is
// within the margin, and its gap is the rim's height, exactly.
TEST(FuzzFindings, TiltedCylinderWithItsRimWithinTheMarginHasASpeculativeContact) {
    const Real r = 1, h = Real(0.5), tilt = Real(15 * 3.14159265358979 / 180);
    const Shape ground = Shape::plane({0, 1, 0}, 0);
    const Shape can = Shape::cylinder(r, h);
    // Tilted about the diagonal between the cap's x and z corners, so the
    // rim's lowest point lies midway between two corners.
    const Quat q = Quat::fromAxisAngle(normalize(Vec3{1, 0, -1}), tilt);
    const double rimBelowCentre = double(h) * std::cos(double(tilt)) + double(r) * std::sin(double(tilt));
    const double cornerAboveRim = double(r) * (1 - std::sqrt(0.5)) * std::sin(double(tilt));  // 0.0758 m
    for (const double height : {0.01, 0.05}) {
        const Transform xb{{0, Real(rimBelowCentre + height), 0}, q};
        const Real margin = Real(0.06);  // under height + cornerAboveRim for both
        ASSERT_GT(height + cornerAboveRim, double(margin));
        ManifoldBuffer out;
        collide(ground, Transform{}, can, xb, margin, out);
        ASSERT_EQ(out.size(), 1u) << "rim " << height << " m over the plane";
        EXPECT_NEAR(-out[0].maxDepth(), height, 1e-5);
    }
    // Beyond the margin the rim gives nothing either.
    ManifoldBuffer out;
    collide(ground, Transform{}, can, Transform{{0, Real(rimBelowCentre + 0.07), 0}, q}, Real(0.06), out);
    EXPECT_TRUE(out.empty());
}
