// Fuzz target: the narrow phase on random shapes and poses (sphere, box,
// capsule, cylinder, hull, plane, mesh, compound). For every manifold of
// collide(a, xa, b, xb, margin):
//   - 1 to 4 points, the normal unit (|n| - 1 within 1e-4) and finite,
//     positions and depths finite, no point shallower than -margin;
//   - collide(b, a) is its mirror bit for bit for two convex shapes of
//     different types (narrow_phase.cpp's promise) not at one point, the
//     same depth within tol for two of one type less than 5 cm deep;
// and against an independent distance, for the pairs that have one:
//   - two convex shapes: GJK's distance d between the full shapes
//     (gjkDistance with the radii), itself checked against 512 sampled
//     directions (none may separate the shapes by more). Separated by less
//     than the margin -> a manifold; separated by more -> none; the
//     manifold's gap (-max depth) equals d for every pair without a box;
//     with a box it is taken along the manifold's normal n (a box face's
//     normal or an edge-edge axis) and may exceed d, but never the distance
//     B can travel along -n before it touches A (a speculative contact that
//     over-states that lets the bodies overlap for a step), measured by
//     conservative advancement on GJK (travelAlong);
//     overlapping -> a manifold, max depth >= 0;
//   - a plane and a convex shape: the gap is exactly the shape's lowest
//     point over the plane (ConvexShape::extent); for a cylinder up to
//     0.29 of its radius more (its cap is the square inscribed in the rim).
// All within tol = 1e-3 * max(1, distance of either shape from the origin)
// (single precision; shapes up to 8 m across, up to 17 m from the origin).
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <optional>
#include <vector>

#include "collision/gjk.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/support.hpp"
#include "fulcrum/error.hpp"

namespace {

using namespace fulcrum;

// The pair under test, printed with a finding.
const Shape* gShapeA = nullptr;
const Shape* gShapeB = nullptr;
Transform gXa, gXb;
Real gMargin = 0;

void describe(const char* label, const Shape& s, const Transform& x) {
    std::fprintf(stderr, "%s exact: p %a %a %a, q %a %a %a %a, radius %a, half height %a, half extents %a %a %a\n", label,
                 static_cast<double>(x.p.x), static_cast<double>(x.p.y), static_cast<double>(x.p.z), static_cast<double>(x.q.x),
                 static_cast<double>(x.q.y), static_cast<double>(x.q.z), static_cast<double>(x.q.w),
                 static_cast<double>(s.radius()), static_cast<double>(s.halfHeight()), static_cast<double>(s.halfExtents().x),
                 static_cast<double>(s.halfExtents().y), static_cast<double>(s.halfExtents().z));
    if (s.type() == ShapeType::ConvexHull) {
        for (const Vec3& v : s.hull().vertices) {
            std::fprintf(stderr, "  vertex %a %a %a\n", static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z));
        }
    }
    std::fprintf(stderr, "%s: %s at (%.9g, %.9g, %.9g) q (%.9g, %.9g, %.9g, %.9g), radius %.9g, half height %.9g, bounds (%.6g %.6g %.6g)-(%.6g %.6g %.6g)\n",
                 label, toString(s.type()), x.p.x, x.p.y, x.p.z, x.q.x, x.q.y, x.q.z, x.q.w, s.radius(), s.halfHeight(),
                 s.localBounds().min.x, s.localBounds().min.y, s.localBounds().min.z, s.localBounds().max.x,
                 s.localBounds().max.y, s.localBounds().max.z);
}

[[noreturn]] void fail(const char* what, double got, double want) {
    std::fprintf(stderr, "narrow phase: %s (got %.9g, expected %.9g; margin %.9g)\n", what, got, want, gMargin);
    std::fprintf(stderr, "margin exact: %a\n", static_cast<double>(gMargin));
    if (gShapeA != nullptr) describe("a", *gShapeA, gXa);
    if (gShapeB != nullptr) describe("b", *gShapeB, gXb);
    std::abort();
}

Real inRange(FuzzedDataProvider& in, Real lo, Real hi) {
    return lo + (hi - lo) * static_cast<Real>(in.ConsumeIntegral<std::uint16_t>()) / Real(65535);
}
Real size(FuzzedDataProvider& in) { return inRange(in, Real(0.02), Real(4)); }
Vec3 point(FuzzedDataProvider& in, Real extent) {
    return {inRange(in, -extent, extent), inRange(in, -extent, extent), inRange(in, -extent, extent)};
}
Quat orientation(FuzzedDataProvider& in) {
    const Quat q{inRange(in, -1, 1), inRange(in, -1, 1), inRange(in, -1, 1), inRange(in, -1, 1)};
    const Real n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return n > Real(1e-3) ? normalize(q) : Quat::identity();
}

// A shape, or nothing when the factory refuses the input (a degenerate hull).
std::optional<Shape> makeShape(FuzzedDataProvider& in, int depth) {
    const int kind = in.ConsumeIntegralInRange(0, depth > 0 ? 4 : 7);
    try {
        switch (kind) {
        case 0: return Shape::sphere(size(in));
        case 1: return Shape::box({size(in), size(in), size(in)});
        case 2:
        case 3: {
            // Read in this order (a call's arguments are read in an order the
            // compiler picks), so an input means the same in every build.
            const Real radius = size(in), halfHeight = size(in);
            return kind == 2 ? Shape::capsule(radius, halfHeight) : Shape::cylinder(radius, halfHeight);
        }
        case 4: {
            std::vector<Vec3> points(in.ConsumeIntegralInRange<std::size_t>(4, 16));
            const Real extent = size(in);
            for (Vec3& p : points) p = point(in, extent);
            return Shape::convexHull(points);
        }
        case 5: {
            Vec3 n = point(in, 1);
            if (length(n) < Real(1e-2)) n = {0, 1, 0};
            return Shape::plane(normalize(n), inRange(in, -4, 4));
        }
        case 6: {
            std::vector<Vec3> vertices(in.ConsumeIntegralInRange<std::size_t>(3, 8));
            for (Vec3& v : vertices) v = point(in, 4);
            std::vector<std::array<std::uint32_t, 3>> triangles(in.ConsumeIntegralInRange<std::size_t>(1, 8));
            const auto last = static_cast<std::uint32_t>(vertices.size() - 1);
            for (auto& t : triangles) {
                for (std::uint32_t& i : t) i = in.ConsumeIntegralInRange<std::uint32_t>(0, last);
            }
            return Shape::mesh(vertices, triangles);
        }
        default: {
            std::vector<CompoundChild> children;
            const int count = in.ConsumeIntegralInRange(1, 3);
            for (int i = 0; i < count; ++i) {
                std::optional<Shape> child = makeShape(in, depth + 1);
                if (!child) return std::nullopt;
                children.push_back({*child, Transform{point(in, 2), orientation(in)}});
            }
            return Shape::compound(children);
        }
        }
    } catch (const Error&) {
        return std::nullopt;
    }
}

constexpr Real kShallow = Real(0.05);  // m: "touching" for the same-type order check

// The largest gap between two convex shapes over a fixed set of directions
// (a Fibonacci sphere of 512): a lower bound of their distance, independent
// of GJK.
Real sampledSeparation(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb) {
    const detail::ConvexShape ca = detail::makeConvex(a, xa), cb = detail::makeConvex(b, xb);
    constexpr int kDirections = 512;
    Real best = -1e30f;
    for (int i = 0; i < kDirections; ++i) {
        const Real y = 1 - 2 * (static_cast<Real>(i) + Real(0.5)) / kDirections;
        const Real r = std::sqrt(std::max(Real(0), 1 - y * y));
        const Real phi = Real(2.39996323) * static_cast<Real>(i);  // the golden angle
        const Vec3 d{r * std::cos(phi), y, r * std::sin(phi)};
        Real loA, hiA, loB, hiB;
        ca.extent(d, loA, hiA);
        cb.extent(d, loB, hiB);
        best = std::max({best, loB - hiA, loA - hiB});
    }
    return best;
}

// How far b can travel along -n (unit, from a to b) before it touches a, for
// shapes apart: conservative advancement (Mirtich). Each step moves b by GJK's
// distance over the rate at which the move closes along GJK's normal, which
// cannot make the shapes overlap, so every t reached is a lower bound of the
// answer and the steps converge on it; a move that does not close along that
// normal never meets a (infinity). Stops once past `enough` (the caller only
// asks whether the answer reaches it) or when a step is under `resolution`.
Real travelAlong(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, const Vec3& n, Real enough,
                 Real resolution) {
    const detail::ConvexShape ca = detail::makeConvex(a, xa);
    Real t = 0;
    for (int i = 0; i < 100 && t <= enough; ++i) {
        const detail::GjkResult g = detail::gjkDistance(ca, detail::makeConvex(b, {xb.p - n * t, xb.q}), true);
        if (g.overlap) break;
        const Real closing = dot(g.normal, n);
        if (closing <= 0) return 1e30f;
        const Real step = g.distance / closing;
        t += step;
        if (step < resolution) break;
    }
    return t;
}

bool isConvex(ShapeType t) { return t != ShapeType::Plane && t != ShapeType::Mesh && t != ShapeType::Compound; }
bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void checkManifolds(const ManifoldBuffer& out, Real margin, Real tol) {
    for (const Manifold& m : out) {
        if (m.pointCount < 1 || m.pointCount > Manifold::kMaxPoints) fail("manifold point count", m.pointCount, 1);
        if (!finite(m.normal)) fail("normal not finite", m.normal.x, 0);
        if (std::fabs(length(m.normal) - 1) > Real(1e-4)) fail("normal not unit", length(m.normal), 1);
        for (const ContactPoint& c : m.contacts()) {
            if (!finite(c.position) || !finite(c.localAnchorA) || !finite(c.localAnchorB)) fail("point not finite", 0, 0);
            if (!std::isfinite(c.depth)) fail("depth not finite", c.depth, 0);
            if (c.depth < -margin - tol) fail("point shallower than the margin", c.depth, -margin);
        }
    }
}

void checkMirror(const ManifoldBuffer& ab, const ManifoldBuffer& ba) {
    if (ab.size() != ba.size()) fail("collide(b, a) has another manifold count", static_cast<double>(ba.size()), static_cast<double>(ab.size()));
    for (std::size_t i = 0; i < ab.size(); ++i) {
        const Manifold &m = ab[i], &r = ba[i];
        if (m.pointCount != r.pointCount) fail("collide(b, a) has another point count", r.pointCount, m.pointCount);
        if (!(r.normal.x == -m.normal.x && r.normal.y == -m.normal.y && r.normal.z == -m.normal.z)) {
            std::fprintf(stderr, "normals: (%.9g %.9g %.9g) and (%.9g %.9g %.9g)\n", m.normal.x, m.normal.y, m.normal.z, r.normal.x,
                         r.normal.y, r.normal.z);
            fail("collide(b, a)'s normal is not the mirror", r.normal.x, -m.normal.x);
        }
        for (std::uint32_t k = 0; k < m.pointCount; ++k) {
            if (!(r.points[k].depth == m.points[k].depth)) fail("collide(b, a) has another depth", r.points[k].depth, m.points[k].depth);
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    const std::optional<Shape> a = makeShape(in, 0);
    if (!a) return 0;
    const std::optional<Shape> b = makeShape(in, 0);
    if (!b) return 0;
    const Transform xa{point(in, 10), orientation(in)}, xb{point(in, 10), orientation(in)};
    const Real margin = inRange(in, 0, Real(0.5));
    gShapeA = &*a;
    gShapeB = &*b;
    gXa = xa;
    gXb = xb;
    gMargin = margin;

    // Shapes at one and the same point have no direction between them: each
    // pair function then takes a fixed fallback normal, the same for (a, b)
    // and (b, a), so no mirror is possible there.
    const bool samePoint = xa.p.x == xb.p.x && xa.p.y == xb.p.y && xa.p.z == xb.p.z;
    ManifoldBuffer ab, ba;
    collide(*a, xa, *b, xb, margin, ab);
    collide(*b, xb, *a, xa, margin, ba);
    const Real tol = Real(1e-3) * std::max({Real(1), length(xa.p), length(xb.p)});
    checkManifolds(ab, margin, tol);
    // The dispatcher runs pairs of two different convex kinds in one order
    // and flips the result, so that collide(b, a) is the exact mirror; two of
    // one kind (hull-hull, box-box) run in the order given. Touching, the two
    // orders then agree to within rounding; deep in each other, the clipped
    // depth is measured from the reference face, A's unless B's is clearly
    // better aligned (collide_convex.cpp), and differs with the order. Apart,
    // two boxes may each take a face of their own as the normal (the same
    // preference for A's face), and the gap along each is the travel along
    // it, checked below for both orders: two boxes 0.238 m apart have gaps of
    // 0.2565 and 0.2453 m along normals 23 degrees apart, each its travel
    // (fuzz/corpus/narrowphase/box_box_orders_take_their_own_faces). The
    // travels along two directions an angle t apart differ by up to about
    // sin t times the pair's reach (the centres' distance plus both radii):
    // two boxes 3.1 m apart whose faces are 0.22 degrees apart have gaps of
    // 0.1509 and 0.1414 m, each its travel
    // (fuzz/corpus/narrowphase/box_box_faces_a_fifth_of_a_degree_apart).
    const ShapeType ta = a->type(), tb = b->type();
    const auto radius = [](const Shape& s) {
        const AABB local = s.localBounds();
        return std::max(length(local.min), length(local.max));
    };
    const auto apartAlongOwnNormals = [&] {
        if (!(-ab[0].maxDepth() > tol && -ba[0].maxDepth() > tol)) return false;
        const Real sinAngle = length(cross(ab[0].normal, ba[0].normal));
        const Real allowed = tol + sinAngle * (length(xa.p - xb.p) + radius(*a) + radius(*b));
        return dot(ab[0].normal, ba[0].normal) < 0 && std::fabs(ab[0].maxDepth() - ba[0].maxDepth()) <= allowed;
    };
    if (!samePoint && isConvex(ta) && isConvex(tb) && ta != tb) {
        checkMirror(ab, ba);
    } else if (isConvex(ta) && isConvex(tb) && ta == tb && !ab.empty() && !ba.empty() &&
               std::max(ab[0].maxDepth(), ba[0].maxDepth()) < kShallow && !apartAlongOwnNormals() &&
               std::fabs(ab[0].maxDepth() - ba[0].maxDepth()) > tol) {
        fail("collide(b, a)'s depth differs from collide(a, b)'s", ba[0].maxDepth(), ab[0].maxDepth());
    }
    const Real gap = ab.empty() ? 0 : -ab[0].maxDepth();
    if (isConvex(ta) && isConvex(tb)) {
        const detail::GjkResult g = detail::gjkDistance(detail::makeConvex(*a, xa), detail::makeConvex(*b, xb), true);
        // Near the origin GJK's distance is noise: under 1e-4 m it means
        // touching or overlapping, as the narrow phase itself reads it
        // (collide_convex.cpp, kCoreTouch); with a cylinder, whose rim GJK
        // converges on slowly, under 1e-3 m (a sphere 4 cm into a thin disk
        // came out 0.4 mm away).
        const bool withCylinder = ta == ShapeType::Cylinder || tb == ShapeType::Cylinder;
        const Real noise = withCylinder ? Real(1e-3) : Real(1e-4);
        const Real d = g.overlap || g.distance < noise ? 0 : g.distance;
        // GJK itself against 512 sampled directions, each a lower bound of
        // the distance: none may separate the shapes more than GJK says (it
        // once claimed overlaps for shapes 0.6 m and 1 m apart, and distances
        // for shapes deep in each other; docs/reliability.md).
        const Real sampled = sampledSeparation(*a, xa, *b, xb);
        if (sampled > (g.overlap ? Real(0) : g.distance) + tol) {
            fail("a sampled direction separates the shapes more than GJK", sampled, g.distance);
        }
        if (ab.size() > 1) fail("two convex shapes gave several manifolds", static_cast<double>(ab.size()), 1);
        if (d < margin - tol && ab.empty()) {
            fail("no manifold for shapes closer than the margin", d, margin);
        }
        // With a box, the gap may be taken along a box face's normal
        // when that separates nearly as well (SAT for box-box, the face
        // test of collide_convex.cpp otherwise): a lower bound of d. Such a
        // speculative manifold is conservative (the solver lets the bodies
        // close the gap it reports, never more), and it exists whenever that
        // gap is within the margin, even where d is not: two aligned cubes
        // corner to corner along their diagonal, 0.099 m apart on each face
        // axis, are 0.171 m apart in truth (fuzz/corpus/narrowphase/
        // aligned_cubes_corner_to_corner).
        const bool withBox = ta == ShapeType::Box || tb == ShapeType::Box;
        const Real reported = withBox && !ab.empty() ? std::min(d, gap) : d;
        if (reported > margin + tol && !ab.empty()) fail("a manifold for shapes farther apart than the margin", d, margin);
        if (!ab.empty()) {
            if (!withBox && gap > d + tol) fail("the manifold's gap exceeds the GJK distance", gap, d);
            if (!withBox && d > 0 && gap < d - tol) fail("the manifold's gap is below the GJK distance", gap, d);
            // The travel along n is at least d, so only a gap beyond d needs
            // it (two boxes apart whose nearest part of B lies outside the
            // reference face: fuzz/corpus/narrowphase/box_box_gap_exceeds_distance,
            // a gap 2 cm over d and equal to the travel).
            if (gap > d + tol) {
                const Real travel = d > 0 ? travelAlong(*a, xa, *b, xb, ab[0].normal, gap, Real(1e-6)) : 0;
                if (gap > travel + tol) fail("the manifold's gap exceeds the distance B can travel along the normal", gap, travel);
            }
        }
        // The same for collide(b, a), which for two of one kind has a
        // normal of its own.
        const Real gapBA = ba.empty() ? 0 : -ba[0].maxDepth();
        if (!ba.empty() && gapBA > d + tol) {
            const Real travel = d > 0 ? travelAlong(*b, xb, *a, xa, ba[0].normal, gapBA, Real(1e-6)) : 0;
            if (gapBA > travel + tol) fail("collide(b, a)'s gap exceeds the distance A can travel along its normal", gapBA, travel);
        }
    } else if ((ta == ShapeType::Plane) != (tb == ShapeType::Plane) && (isConvex(ta) || isConvex(tb))) {
        const bool planeFirst = ta == ShapeType::Plane;
        const Shape& plane = planeFirst ? *a : *b;
        const Transform& xp = planeFirst ? xa : xb;
        const Vec3 n = rotate(xp.q, plane.planeNormal());
        const Real offset = plane.planeOffset() + dot(n, xp.p);
        Real lo, hi;
        detail::makeConvex(planeFirst ? *b : *a, planeFirst ? xb : xa).extent(n, lo, hi);
        const Real d = lo - offset;  // the shape's lowest point over the plane
        if (d < margin - tol && ab.empty()) fail("no manifold for a shape closer to the plane than the margin", d, margin);
        if (d > margin + tol && !ab.empty()) fail("a manifold for a shape farther from the plane than the margin", d, margin);
        // A cylinder's cap is the square inscribed in its rim (support.hpp,
        // kCylinderCapPoints): tilted onto the plane, its corners reach up to
        // (1 - cos 45 deg) of the radius less deep than the rim.
        const Shape& other = planeFirst ? *b : *a;
        const Real capSlack = other.type() == ShapeType::Cylinder ? Real(0.2929) * other.radius() : 0;
        if (!ab.empty() && (gap < d - tol || gap > d + capSlack + tol)) {
            fail("the manifold's gap differs from the height over the plane", gap, d);
        }
    }
    return 0;
}
